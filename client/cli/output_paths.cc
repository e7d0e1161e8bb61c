#include "client/cli/output_paths.h"

#include "absl/strings/match.h"
#include "absl/strings/string_view.h"

namespace mocap::cli {

ReconstructionOutputPaths OutputPathsOf(const std::string& output) {
  std::string prefix = output;
  for (const absl::string_view extension : {".bvh", ".json"}) {
    // Not a bare ".bvh": that is a prefix of its own (a hidden file's name), not an extension.
    if (prefix.size() > extension.size() && absl::EndsWithIgnoreCase(prefix, extension) &&
        prefix[prefix.size() - extension.size() - 1] != '/') {
      prefix.resize(prefix.size() - extension.size());
      break;
    }
  }
  return {prefix + ".bvh", prefix + ".json"};
}

}  // namespace mocap::cli

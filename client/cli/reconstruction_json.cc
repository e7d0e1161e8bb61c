#include "client/cli/reconstruction_json.h"

#include <algorithm>
#include <fstream>
#include <string>
#include <string_view>

#include "client/cli/cli_common.h"

namespace mocap::cli {
namespace {

// The frames field of the top-level object as Json() prints it empty: one space of indent per
// level, so this text is the top level's alone.
constexpr std::string_view kEmptyFrames = "\n \"frames\": []";

// One frame's text as an element of the top-level array: every line two levels deeper.
void WriteIndentedElement(std::string_view text, std::ofstream& out) {
  while (!text.empty() && text.back() == '\n') text.remove_suffix(1);
  size_t begin = 0;
  while (begin <= text.size()) {
    const size_t end = std::min(text.find('\n', begin), text.size());
    out << (begin == 0 ? "  " : "\n  ") << text.substr(begin, end - begin);
    begin = end + 1;
  }
}

}  // namespace

absl::Status WriteReconstructionJson(const std::filesystem::path& path, const v1::ReconstructTrajectoryResponse& answer,
                                     const std::vector<v1::Frame>& frames) {
  if (answer.frames_size() > 0) return absl::InvalidArgumentError("the answer's frames are written apart");
  const std::string rest = Json(answer);
  const size_t at = rest.find(kEmptyFrames);
  if (at == std::string::npos) return absl::InternalError("no top-level frames field in the answer's JSON");
  std::ofstream out(path, std::ios::binary);
  out << std::string_view(rest).substr(0, at) << "\n \"frames\": [";
  for (size_t i = 0; i < frames.size(); ++i) {
    out << (i == 0 ? "\n" : ",\n");
    WriteIndentedElement(Json(frames[i]), out);
  }
  out << (frames.empty() ? "]" : "\n ]") << std::string_view(rest).substr(at + kEmptyFrames.size());
  if (!out) return absl::DataLossError("cannot write " + path.string());
  return absl::OkStatus();
}

}  // namespace mocap::cli

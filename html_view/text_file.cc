#include "html_view/text_file.h"

#include <fstream>
#include <sstream>

namespace mocap::html_view {

absl::StatusOr<std::string> ReadTextFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  if (in) text << in.rdbuf();
  if (!in) return absl::NotFoundError("cannot read " + path.string());
  return text.str();
}

absl::Status WriteTextFile(const std::filesystem::path& path, std::string_view text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) return absl::DataLossError("cannot write " + path.string());
  return absl::OkStatus();
}

}  // namespace mocap::html_view

#include "motion/bvh/bvh_files.h"

#include <algorithm>
#include <set>

#include "motion/core/str_cat.h"

namespace mocap {

absl::StatusOr<std::vector<std::filesystem::path>> CollectBvhFiles(const std::vector<std::string>& inputs) {
  std::vector<std::filesystem::path> files;
  for (const std::string& input : inputs) {
    std::error_code error;
    const std::filesystem::path path(input);
    if (std::filesystem::is_directory(path, error)) {
      std::vector<std::filesystem::path> found;
      for (auto it = std::filesystem::recursive_directory_iterator(path, error);
           !error && it != std::filesystem::recursive_directory_iterator(); it.increment(error)) {
        std::string extension = it->path().extension().string();
        std::transform(extension.begin(), extension.end(), extension.begin(), ::tolower);
        if (it->is_regular_file() && extension == ".bvh") found.push_back(it->path());
      }
      if (error) return absl::InvalidArgumentError(StrCat(input, ": ", error.message()));
      std::sort(found.begin(), found.end());  // a folder's files in path order
      files.insert(files.end(), found.begin(), found.end());
    } else if (std::filesystem::is_regular_file(path, error)) {
      files.push_back(path);
    } else {
      return absl::InvalidArgumentError(StrCat(input, ": no such file or folder"));
    }
  }
  if (files.empty()) return absl::InvalidArgumentError("no .bvh files found in the given inputs");
  // In the order named (the first names the database's rig), each file once.
  std::vector<std::filesystem::path> unique;
  std::set<std::filesystem::path> seen;
  for (std::filesystem::path& file : files) {
    if (seen.insert(file.lexically_normal()).second) unique.push_back(std::move(file));
  }
  return unique;
}

}  // namespace mocap

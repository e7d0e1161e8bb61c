// The BVH files a command line names: files as given, folders searched recursively.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "absl/status/statusor.h"

namespace mocap {

// Sorted *.bvh files under `inputs`; InvalidArgument when an input does not exist or none found.
absl::StatusOr<std::vector<std::filesystem::path>> CollectBvhFiles(const std::vector<std::string>& inputs);

}  // namespace mocap

// The BVH files a command line names: files as given, folders searched recursively.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "absl/status/statusor.h"

namespace mocap {

// The *.bvh files of `inputs` in the order named (a folder's files, recursively, in path order),
// each once; InvalidArgument when an input does not exist or none is found. Order matters: the
// first file names a new database's rig.
absl::StatusOr<std::vector<std::filesystem::path>> CollectBvhFiles(const std::vector<std::string>& inputs);

}  // namespace mocap

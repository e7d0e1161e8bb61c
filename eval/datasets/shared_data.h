// The shared motion data (../shared/data: archives and unpack.sh) for the evaluation harness, the
// benchmarks and the tests: where it is, sets unpacked on first use into a cache folder, their
// BVH files. Nothing is fixed at build time: tools take the folders from options or the
// environment, so an installed binary works wherever the data is.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mocap::datasets {

struct DataLocation {
  std::filesystem::path shared_dir;  // holds unpack.sh and the archives
  std::filesystem::path cache_dir;   // where sets are unpacked, one folder each
};

// $MOCAP_SHARED_DATA_DIR, else `shared_dir_fallback`; $MOCAP_DATA_CACHE_DIR, else
// $XDG_CACHE_HOME/mocap/data, else ~/.cache/mocap/data.
DataLocation DataLocationFromEnvironment(const std::filesystem::path& shared_dir_fallback = "../shared/data");

// Folder of the unpacked set `name` ("bandai-namco-1", "bandai-namco-2", "cmu-cc"), unpacking it
// with unpack.sh when needed (serialised between processes with flock). nullopt, with `why`, when
// the shared data is not there or unpacking failed.
std::optional<std::filesystem::path> UnpackedSet(const DataLocation& location, std::string_view name, std::string* why);

// The sorted .bvh files under a folder (motion/bvh/bvh_files.h; empty when there are none).
std::vector<std::filesystem::path> BvhFilesIn(const std::filesystem::path& folder);

}  // namespace mocap::datasets

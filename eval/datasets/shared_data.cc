#include "eval/datasets/shared_data.h"

#include <cstdlib>

#include "motion/bvh/bvh_files.h"

namespace mocap::datasets {
namespace {

std::filesystem::path DefaultCacheDir() {
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg != nullptr && *xdg != '\0') {
    return std::filesystem::path(xdg) / "mocap" / "data";
  }
  const char* home = std::getenv("HOME");
  return std::filesystem::path(home != nullptr ? home : ".") / ".cache" / "mocap" / "data";
}

}  // namespace

DataLocation DataLocationFromEnvironment(const std::filesystem::path& shared_dir_fallback) {
  const char* shared = std::getenv("MOCAP_SHARED_DATA_DIR");
  const char* cache = std::getenv("MOCAP_DATA_CACHE_DIR");
  return {.shared_dir = shared != nullptr && *shared != '\0' ? std::filesystem::path(shared) : shared_dir_fallback,
          .cache_dir = cache != nullptr && *cache != '\0' ? std::filesystem::path(cache) : DefaultCacheDir()};
}

std::optional<std::filesystem::path> UnpackedSet(const DataLocation& location, std::string_view name,
                                                 std::string* why) {
  const std::filesystem::path folder = location.cache_dir / std::string(name);
  if (std::filesystem::exists(folder / ".complete")) return folder;
  const std::filesystem::path unpack = location.shared_dir / "unpack.sh";
  if (!std::filesystem::exists(unpack)) {
    *why = "no " + unpack.string() + " (put ../shared beside the repository, or set MOCAP_SHARED_DATA_DIR)";
    return std::nullopt;
  }
  // Test processes run in parallel: serialise unpacking (unpack.sh is not safe to run twice at
  // once on one folder).
  std::error_code error;
  std::filesystem::create_directories(location.cache_dir, error);
  const std::string command = "flock '" + (location.cache_dir / ".unpack.lock").string() + "' bash '" +
                              unpack.string() + "' '" + location.cache_dir.string() + "' " + std::string(name) + " >&2";
  if (std::system(command.c_str()) != 0 || !std::filesystem::exists(folder / ".complete")) {
    *why = "unpacking " + std::string(name) + " with " + unpack.string() + " failed";
    return std::nullopt;
  }
  return folder;
}

std::vector<std::filesystem::path> BvhFilesIn(const std::filesystem::path& folder) {
  absl::StatusOr<std::vector<std::filesystem::path>> files = CollectBvhFiles({folder.string()});
  return files.ok() ? *std::move(files) : std::vector<std::filesystem::path>{};
}

}  // namespace mocap::datasets

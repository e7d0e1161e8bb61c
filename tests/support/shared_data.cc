#include "tests/support/shared_data.h"

#include <algorithm>
#include <cstdlib>

namespace mocap::testing {

std::optional<std::filesystem::path> SharedDataSet(std::string_view name, std::string* why) {
  const char* env_shared = std::getenv("MOCAP_SHARED_DATA_DIR");
  const std::filesystem::path shared = env_shared ? env_shared : MOCAP_SHARED_DATA_DIR;
  const char* env_cache = std::getenv("MOCAP_DATA_CACHE_DIR");
  const std::filesystem::path cache = env_cache ? env_cache : MOCAP_DATA_CACHE_DIR;
  const std::filesystem::path folder = cache / std::string(name);
  if (std::filesystem::exists(folder / ".complete")) return folder;
  const std::filesystem::path unpack = shared / "unpack.sh";
  if (!std::filesystem::exists(unpack)) {
    *why = "no " + unpack.string() + " (run tests with ../shared beside the repository)";
    return std::nullopt;
  }
  // ctest runs test processes in parallel: serialise unpacking (unpack.sh is not safe to run
  // twice at once on one folder).
  std::filesystem::create_directories(cache);
  const std::string command = "flock '" + (cache / ".unpack.lock").string() + "' bash '" + unpack.string() + "' '" +
                              cache.string() + "' " + std::string(name) + " >&2";
  if (std::system(command.c_str()) != 0 || !std::filesystem::exists(folder / ".complete")) {
    *why = "unpacking " + std::string(name) + " with " + unpack.string() + " failed";
    return std::nullopt;
  }
  return folder;
}

std::vector<std::filesystem::path> BvhFilesIn(const std::filesystem::path& folder) {
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    if (entry.path().extension() == ".bvh") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::filesystem::path TestDataDir() { return MOCAP_TESTDATA_DIR; }

}  // namespace mocap::testing

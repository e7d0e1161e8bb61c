#include "tests/support/shared_data.h"

#include <cstdlib>

#include "eval/datasets/shared_data.h"

namespace mocap::testing {

std::optional<std::filesystem::path> SharedDataSet(std::string_view name, std::string* why) {
  // Tests find ../shared/data from the source tree (they run in the build tree); the environment
  // still wins, as for the tools.
  datasets::DataLocation location = datasets::DataLocationFromEnvironment(MOCAP_SHARED_DATA_DIR);
  if (std::getenv("MOCAP_DATA_CACHE_DIR") == nullptr) location.cache_dir = MOCAP_DATA_CACHE_DIR;
  return datasets::UnpackedSet(location, name, why);
}

std::vector<std::filesystem::path> BvhFilesIn(const std::filesystem::path& folder) {
  return datasets::BvhFilesIn(folder);
}

std::filesystem::path TestDataDir() { return MOCAP_TESTDATA_DIR; }

}  // namespace mocap::testing

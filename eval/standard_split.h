// The standard evaluation split of shared/data/README, for mocap-eval and the benchmarks: database = bandai-namco-2
// clips whose take is not ≡ 3 (mod 10), test = takes ≡ 3 (mod 10).
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "eval/datasets/shared_data.h"
#include "motion/preprocess/clip_preprocessor.h"

namespace mocap::eval {

struct StandardSplit {
  std::filesystem::path folder;
  std::vector<std::filesystem::path> database_files;
  std::vector<std::filesystem::path> test_files;
  RigModel rig;  // from the first database file
};

// Unpacks bandai-namco-2 when needed; NotFound when the shared data is absent.
absl::StatusOr<StandardSplit> LoadStandardSplit(
    const datasets::DataLocation& data = datasets::DataLocationFromEnvironment());

// The development split, for choosing methods and parameters without looking at the standard
// split's test clips: test = takes ≡ 5 (mod 10); database = takes ≢ 3 and ≢ 5 (mod 10), so the
// standard split's test clips are in neither part.
absl::StatusOr<StandardSplit> LoadDevelopmentSplit(
    const datasets::DataLocation& data = datasets::DataLocationFromEnvironment());

// Reads and prepares `files` on all cores, handing each result to `consume(index, clip)` from
// the worker threads (calls for different indices may run at once). Returns the first error.
absl::Status PrepareAll(const std::vector<std::filesystem::path>& files, const RigModel& rig,
                        const std::function<void(size_t, PreparedClip&&)>& consume);

}  // namespace mocap::eval

#include "eval/standard_split.h"

#include "eval/parallel_for.h"
#include "motion/bvh/bvh_reader.h"
#include "motion/core/status_macros.h"
#include "motion/preprocess/clip_labels.h"

namespace mocap::eval {

namespace {

// Test takes ≡ `test_residue` (mod 10); takes ≡ `excluded_residue` are in neither part (−1: none).
absl::StatusOr<StandardSplit> LoadSplit(const datasets::DataLocation& data, int test_residue, int excluded_residue) {
  std::string why;
  auto folder = datasets::UnpackedSet(data, "bandai-namco-2", &why);
  if (!folder) return absl::NotFoundError("shared data unavailable: " + why);
  StandardSplit split;
  split.folder = *folder;
  for (const std::filesystem::path& file : datasets::BvhFilesIn(*folder)) {
    const std::string take = LabelValue(ParseClipLabels(file.filename().string()), "take");
    if (take.empty()) continue;
    const int residue = std::stoi(take) % 10;
    if (residue == excluded_residue) continue;
    (residue == test_residue ? split.test_files : split.database_files).push_back(file);
  }
  if (split.database_files.empty() || split.test_files.empty()) return absl::NotFoundError("no bandai-namco-2 takes");
  MOCAP_ASSIGN_OR_RETURN(BvhClip first, ReadBvhFile(split.database_files.front()));
  MOCAP_ASSIGN_OR_RETURN(split.rig, BuildRigModel(first, {}));
  return split;
}

}  // namespace

absl::StatusOr<StandardSplit> LoadStandardSplit(const datasets::DataLocation& data) { return LoadSplit(data, 3, -1); }
absl::StatusOr<StandardSplit> LoadDevelopmentSplit(const datasets::DataLocation& data) { return LoadSplit(data, 5, 3); }

absl::Status PrepareAll(const std::vector<std::filesystem::path>& files, const RigModel& rig,
                        const std::function<void(size_t, PreparedClip&&)>& consume) {
  return ParallelFor(files.size(), AllCores(), [&](size_t i) -> absl::Status {
    MOCAP_ASSIGN_OR_RETURN(BvhClip clip, ReadBvhFile(files[i]));
    MOCAP_ASSIGN_OR_RETURN(PreparedClip prepared, PrepareClip(clip, rig, {}));
    consume(i, std::move(prepared));
    return absl::OkStatus();
  });
}

}  // namespace mocap::eval

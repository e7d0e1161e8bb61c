#include "server/reconstruction_databases.h"

#include <spdlog/spdlog.h>

#include "motion/core/status_macros.h"

namespace mocap {

absl::StatusOr<ReconstructionDatabases::Database> ReconstructionDatabases::Load(MotionStore& store, const Key& key,
                                                                                bool time_reversed_copies) {
  MOCAP_ASSIGN_OR_RETURN(RigModel rig, store.LoadRig(key.database));
  MOCAP_ASSIGN_OR_RETURN(std::vector<ClipSummary> summaries, store.ListClips(key.database));
  if (summaries.empty()) return absl::FailedPreconditionError("the database has no clips: import motion into it first");
  std::vector<DatabaseClip> clips;
  clips.reserve(summaries.size());
  for (const ClipSummary& summary : summaries) {
    MOCAP_ASSIGN_OR_RETURN(StoredClip clip, store.LoadClip(key.database, summary.id, rig));
    clips.push_back({std::move(clip.features), EncodePoses(clip.motion, rig)});
  }
  const double frame_rate = key.frame_rate > 0 ? key.frame_rate : 30.0;
  MOCAP_ASSIGN_OR_RETURN(
      Database database,
      ReconstructionDatabase::Build(rig, clips,
                                    {.frame_time = 1.0 / frame_rate, .time_reversed_copies = time_reversed_copies}));
  // What --cached-databases costs an operator: the indices' memory, per frame as the docs size it.
  const size_t bytes = database->memory_use().total();
  spdlog::info(
      "reconstruction indices of database {}: {} frames ({} searchable rows), {:.1f} MB, {:.0f} bytes per frame",
      key.database.id(), database->num_frames(), database->num_rows(), static_cast<double>(bytes) / 1e6,
      static_cast<double>(bytes) / database->num_frames());
  return database;
}

}  // namespace mocap

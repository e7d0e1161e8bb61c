// `mocapd similar`: cross-skeleton similar-pose search on a store file (METHOD.md B; issue #5).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "absl/status/statusor.h"
#include "motion/similarity/pose_index.h"

namespace mocap {

struct SimilarOptions {
  std::filesystem::path store;
  std::string tenant;                   // tenant name; empty: the default tenant
  std::vector<std::string> databases;   // searched together; matches merged by distance
  std::filesystem::path query;          // a BVH file on any humanoid rig, or
  std::optional<nlohmann::json> pose;   // one pose as joint positions with the landmarks named:
  // {"units": "m", "up": "+Y", "joints": [{"name": "Hips", "parent": null, "position": [x, y, z]},
  //  ...], "landmarks": {"pelvis": "Hips", "head": ..., "left_wrist": ..., "right_wrist": ...,
  //  "left_ankle": ..., "right_ankle": ...}}   (parents listed before children)
  std::optional<int> first_frame;       // query frames in the file's own numbering (inclusive)
  std::optional<int> last_frame;
  int frame_step = 1;
  PoseSearchOptions search;
  BodyPointOptions points;
};

// Per query frame, the matches with the clip's file name, frame index (in the clip's own frame
// numbering, and at the database rate), distance, per-group distances and alignment.
absl::StatusOr<nlohmann::json> RunSimilar(const SimilarOptions& options);

}  // namespace mocap

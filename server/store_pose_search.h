// Cross-skeleton similar-pose search straight on a store file (docs/method.md B), without a server:
// what `mocapd similar` runs. The same search and answer as the PoseSearch service.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "mocap/v1/pose_search.pb.h"
#include "motion/similarity/pose_index.h"

namespace mocap {

struct SimilarOptions {
  std::filesystem::path store;
  std::string tenant;                  // tenant name; empty: the default tenant
  std::vector<std::string> databases;  // searched together; matches merged by distance
  std::filesystem::path query;         // a BVH file on any humanoid rig, or
  std::optional<v1::NamedPose> pose;   // one pose as named joint positions with its landmarks
  std::optional<int> first_frame;      // query frames in the file's own numbering (inclusive)
  std::optional<int> last_frame;
  int frame_step = 1;
  PoseSearchOptions search;
  BodyPointOptions points;
};

// Per query frame, the matches with the clip's file name, frame index (in the clip's own frame
// numbering, and at the database rate), distance, per-group distances and alignment: the
// PoseSearch service's answer, so that both print through tools/similar_json.
absl::StatusOr<v1::FindSimilarPosesResponse> FindSimilarPosesInStore(const SimilarOptions& options);

}  // namespace mocap

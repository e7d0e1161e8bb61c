#include "motion/reconstruct/ankle_cloud.h"

#include "motion/core/status_macros.h"

namespace mocap {

FrameFeatures WristQueryFeatures(const ReferenceFrame& ref, const SmoothedWrists& wrists) {
  FrameFeatures query{};
  for (int side = 0; side < 2; ++side) {
    const Eigen::Vector3f p = ref.ToLocal(wrists.position[side]);
    const Eigen::Vector3f v = ref.DirectionToLocal(wrists.velocity[side]);
    for (int axis = 0; axis < 3; ++axis) {
      query.wrist_position[side][axis] = p[axis];
      query.wrist_velocity[side][axis] = v[axis];
    }
  }
  return query;
}

absl::Status FindAnkleCloud(const WristFeatureIndex& index, const std::vector<DatabaseFrame>& database,
                            const WristFeatureOptions& feature_options, const SmoothedWrists& wrists, int k,
                            float* heading, std::vector<AnkleCandidate>* cloud) {
  for (int side = 0; side < 2; ++side) {
    if (!wrists.position[side].allFinite() || !wrists.velocity[side].allFinite()) {
      return absl::InvalidArgumentError("wrist sample is not finite");
    }
  }
  const ReferenceFrame ref = WristReferenceFrame(wrists.position[0], wrists.position[1], *heading, heading);
  const FrameFeatures query = WristQueryFeatures(ref, wrists);
  float feature[kWristFeatureDims];
  WristFeature(query, feature_options, feature);
  MOCAP_ASSIGN_OR_RETURN(std::vector<Neighbour> neighbours, index.Search(feature, k));
  cloud->resize(neighbours.size());
  for (size_t i = 0; i < neighbours.size(); ++i) {
    const DatabaseFrame& f = database[neighbours[i].row];
    AnkleCandidate& candidate = (*cloud)[i];
    candidate.row = neighbours[i].row;
    candidate.wrist_distance = neighbours[i].distance;
    for (int side = 0; side < 2; ++side) {
      // The neighbour's ankles are in its own wrist frame; the same local coordinates in the
      // query's wrist frame give the query-world positions (docs/method.md A1, A3).
      candidate.position[side] =
          ref.origin + ref.rotation * Eigen::Vector3f(f.ankle_position[side][0], f.ankle_position[side][1],
                                                      f.ankle_position[side][2]);
      candidate.velocity[side] = ref.rotation * Eigen::Vector3f(f.ankle_velocity[side][0], f.ankle_velocity[side][1],
                                                                f.ankle_velocity[side][2]);
    }
  }
  return absl::OkStatus();
}

}  // namespace mocap

#include "motion/reconstruct/wrist_feature_index.h"

#include <algorithm>
#include <cmath>

namespace mocap {

void WristFeature(const FrameFeatures& features, const WristFeatureOptions& options, float out[kWristFeatureDims]) {
  const float p = std::sqrt(options.position_weight);
  const float v = std::sqrt(1.0f - options.position_weight);
  for (int side = 0; side < 2; ++side) {
    for (int axis = 0; axis < 3; ++axis) {
      out[3 * side + axis] = p * features.wrist_position[side][axis];
      out[6 + 3 * side + axis] = v * features.wrist_velocity[side][axis];
    }
  }
}

std::vector<float> WristFeatures(const std::vector<FrameFeatures>& frames, const WristFeatureOptions& options) {
  std::vector<float> points(frames.size() * kWristFeatureDims);
  for (size_t i = 0; i < frames.size(); ++i) WristFeature(frames[i], options, points.data() + i * kWristFeatureDims);
  return points;
}

absl::Status WristFeatureIndex::Build(const std::vector<FrameFeatures>& frames, const WristFeatureOptions& options) {
  if (frames.empty()) return absl::FailedPreconditionError("no frames to index");
  if (!(options.position_weight >= 0.0f && options.position_weight <= 1.0f)) {
    return absl::InvalidArgumentError("position weight α must lie in [0, 1]");
  }
  return tree_.Build(WristFeatures(frames, options), kWristFeatureDims);
}

absl::StatusOr<std::vector<Neighbour>> WristFeatureIndex::Search(const float query[kWristFeatureDims], int k) const {
  return tree_.Search(query, k);
}

}  // namespace mocap

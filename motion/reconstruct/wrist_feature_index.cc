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

absl::Status WristFeatureIndex::Build(const std::vector<FrameFeatures>& frames, const WristFeatureOptions& options) {
  if (frames.empty()) return absl::FailedPreconditionError("no frames to index");
  if (!(options.position_weight >= 0.0f && options.position_weight <= 1.0f)) {
    return absl::InvalidArgumentError("position weight α must lie in [0, 1]");
  }
  std::vector<float> points(frames.size() * kWristFeatureDims);
  for (size_t i = 0; i < frames.size(); ++i) WristFeature(frames[i], options, points.data() + i * kWristFeatureDims);
  return tree_.Build(std::move(points), kWristFeatureDims);
}

absl::StatusOr<std::vector<Neighbour>> WristFeatureIndex::Search(const float query[kWristFeatureDims], int k) const {
  return tree_.Search(query, k);
}

absl::StatusOr<std::vector<Neighbour>> WristFeatureIndex::SearchBruteForce(const float query[kWristFeatureDims],
                                                                           int k) const {
  if (tree_.size() == 0) return absl::FailedPreconditionError("wrist index is not built");
  if (k < 1) return absl::InvalidArgumentError("k must be at least 1");
  std::vector<Neighbour> all(tree_.size());
  for (int row = 0; row < tree_.size(); ++row) {
    const float* x = tree_.point(row);
    float sum = 0.0f;
    for (int d = 0; d < kWristFeatureDims; ++d) {
      const float diff = x[d] - query[d];
      sum += diff * diff;
    }
    all[row] = {row, sum};
  }
  const size_t count = static_cast<size_t>(std::min(k, tree_.size()));
  std::partial_sort(all.begin(), all.begin() + count, all.end(),
                    [](const Neighbour& a, const Neighbour& b) { return a.distance < b.distance; });
  all.resize(count);
  return all;
}

}  // namespace mocap

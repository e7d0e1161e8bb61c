#include "motion/reconstruct/wrist_reach.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace mocap {
namespace {

float Quantile(std::vector<float>& values, float quantile) {
  const size_t k = std::min(values.size() - 1, static_cast<size_t>(quantile * static_cast<float>(values.size())));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

}  // namespace

WristReach MeasureWristReach(std::span<const FrameFeatures> frames) {
  WristReach reach;
  for (const FrameFeatures& f : frames) {
    const float* l = f.wrist_position[0];
    const float* r = f.wrist_position[1];
    reach.separation = std::max(reach.separation, std::hypot(l[0] - r[0], l[1] - r[1], l[2] - r[2]));
    reach.height = std::max({reach.height, l[1], r[1]});
  }
  return reach;
}

absl::StatusOr<ReachScale> InputScaleFromReach(const WristReach& database, std::span<const WristSample> samples,
                                               const ReachScaleOptions& options) {
  if (!(database.separation > 0.0f) || !(database.height > 0.0f)) {
    return absl::InvalidArgumentError("the database has no wrist reach (no frames)");
  }
  std::vector<float> separation, height;
  separation.reserve(samples.size());
  height.reserve(2 * samples.size());
  for (const WristSample& s : samples) {
    for (int hand = 0; hand < 2; ++hand) {
      const Eigen::Vector3f& p = hand == 0 ? s.left : s.right;
      if (!s.tracked[hand]) continue;
      if (!p.allFinite()) return absl::InvalidArgumentError("a tracked wrist sample is not finite");
      height.push_back(p.y());
    }
    if (s.tracked[0] && s.tracked[1]) separation.push_back((s.left - s.right).norm());
  }
  ReachScale scale;
  if (samples.size() < 2 || samples.back().time - samples.front().time < options.min_seconds) return scale;
  float bound = 1.0f;
  if (!separation.empty()) {
    scale.separation = Quantile(separation, options.quantile);
    if (scale.separation > 0.0f) bound = std::min(bound, database.separation / scale.separation);
  }
  if (!height.empty()) {
    scale.height = Quantile(height, options.quantile);
    if (scale.height > 0.0f) bound = std::min(bound, database.height / scale.height);
  }
  scale.input_scale = std::max(options.min_scale, bound);
  return scale;
}

}  // namespace mocap

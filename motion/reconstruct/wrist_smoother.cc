#include "motion/reconstruct/wrist_smoother.h"

namespace mocap {

WristSmoother::WristSmoother(const WristSmoothingOptions& options, double frame_time)
    : options_(options), rate_(static_cast<float>(1.0 / frame_time)) {}

SmoothedWrists WristSmoother::Push(const Eigen::Vector3f& left, const Eigen::Vector3f& right) {
  SmoothedWrists out;
  const Eigen::Vector3f measured[2] = {left, right};
  for (int side = 0; side < 2; ++side) {
    if (!has_previous_) {
      out.position[side] = measured[side];
      out.velocity[side].setZero();
    } else {
      out.position[side] = options_.smoothing * measured[side] + (1.0f - options_.smoothing) * previous_[side];
      out.velocity[side] = (out.position[side] - previous_[side]) * rate_;
    }
    previous_[side] = out.position[side];
  }
  has_previous_ = true;
  return out;
}

void WristSmoother::Reset() { has_previous_ = false; }

}  // namespace mocap

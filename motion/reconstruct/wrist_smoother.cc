#include "motion/reconstruct/wrist_smoother.h"

#include <algorithm>

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

SmoothedWrists LocalLinearWrists(std::span<const std::array<Eigen::Vector3f, 2>> input, int t, int newest,
                                 const std::vector<float>& kernel, float rate) {
  const int r = static_cast<int>(kernel.size()) / 2;
  const int low = std::max(0, t - r), high = std::min(newest, t + r);
  // Weighted least squares of x(i) ≈ a + b·(i − t): a is the position, b·rate the velocity.
  float w_sum = 0, i_mean = 0;
  for (int i = low; i <= high; ++i) {
    w_sum += kernel[i - t + r];
    i_mean += kernel[i - t + r] * static_cast<float>(i - t);
  }
  i_mean /= w_sum;
  float spread = 0;
  for (int i = low; i <= high; ++i) spread += kernel[i - t + r] * (i - t - i_mean) * (i - t - i_mean);
  SmoothedWrists out;
  for (int side = 0; side < 2; ++side) {
    Eigen::Vector3f mean = Eigen::Vector3f::Zero(), slope = Eigen::Vector3f::Zero();
    for (int i = low; i <= high; ++i) mean += kernel[i - t + r] * input[i][side];
    mean /= w_sum;
    if (spread > 1e-6f) {
      for (int i = low; i <= high; ++i) slope += kernel[i - t + r] * (i - t - i_mean) * (input[i][side] - mean);
      slope /= spread;
    }
    out.position[side] = mean - i_mean * slope;  // the fit at i = t
    out.velocity[side] = slope * rate;
  }
  return out;
}

}  // namespace mocap

// Input preprocessing of METHOD.md A2: exponential smoothing of the measured wrists,
//   x̃^t = s·x^t + (1−s)·x̃^(t−1),  s = 0.5,
// and wrist velocities by numerical differentiation of neighbouring (smoothed) samples. Causal:
// usable sample by sample in a stream and identically over a whole clip.
#pragma once

#include <Eigen/Core>

namespace mocap {

struct WristSmoothingOptions {
  float smoothing = 0.5f;  // s, METHOD.md A2; 1 = no smoothing
};

struct SmoothedWrists {
  Eigen::Vector3f position[2];  // [0] left, [1] right; metres, world Y up
  Eigen::Vector3f velocity[2];  // m/s
};

class WristSmoother {
 public:
  WristSmoother(const WristSmoothingOptions& options, double frame_time);

  // Next sample (at the database rate). The first sample passes through with zero velocity; the
  // second's velocity is also given to the first frame by callers that need it.
  SmoothedWrists Push(const Eigen::Vector3f& left, const Eigen::Vector3f& right);
  void Reset();

 private:
  WristSmoothingOptions options_;
  float rate_;
  bool has_previous_ = false;
  Eigen::Vector3f previous_[2];
};

}  // namespace mocap

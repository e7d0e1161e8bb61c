// Input conditioning for a reconstruction: timestamped wrist samples at any rate → samples on the
// database's frame grid (linear interpolation). A dropout up to `max_gap` seconds is bridged by
// interpolation; a longer one ends the segment and a new grid starts at the next sample.
// Non-finite samples and timestamps that do not increase are refused (the resampler's state is
// unchanged, so the caller may continue with the next good sample).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "absl/status/status.h"

namespace mocap {

struct WristSample {
  double time = 0.0;                               // seconds, any origin; strictly increasing
  Eigen::Vector3f left = Eigen::Vector3f::Zero();  // metres, world Y up
  Eigen::Vector3f right = Eigen::Vector3f::Zero();
};

struct GridSample {
  bool starts_segment = false;  // the previous segment (if any) ended before this sample
  bool bridged = false;         // interpolated across a dropout longer than two sample periods
  double time = 0.0;
  Eigen::Vector3f left, right;
};

class WristResampler {
 public:
  WristResampler(double frame_time, double max_gap_seconds);
  // Appends the grid samples this input sample completes.
  absl::Status Push(const WristSample& sample, std::vector<GridSample>* out);
  void Reset() { has_previous_ = false; }

 private:
  double frame_time_, max_gap_;
  bool has_previous_ = false;
  WristSample previous_;
  double typical_period_ = 0.0;
  long next_index_ = 0;  // next grid frame, counted from grid_origin_
  double grid_origin_ = 0.0;
};

}  // namespace mocap

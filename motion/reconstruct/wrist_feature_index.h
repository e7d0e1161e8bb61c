// Nearest database frames to a wrist query under docs/method.md A3, eq. 2:
//   α‖x̃ − x_n‖² + (1−α)‖ẋ̃ − ẋ_n‖²   (both wrists, positions and velocities in their own wrist
// reference frames). The weights are folded into the coordinates (√α, √(1−α)), so the metric is
// plain squared L2 and a FLANN kd-tree answers it exactly (FACTS.md: a single kd-tree with leaf
// size 16 is exact and ~8x faster than brute force for K1 = 1000 on 347k frames).
//
// Thread safety: Build once; Search is const and may run from many threads at once.
#pragma once

#include <memory>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "motion/core/kd_tree.h"
#include "motion/preprocess/frame_features.h"

namespace mocap {

inline constexpr int kWristFeatureDims = 12;

struct WristFeatureOptions {
  float position_weight = 0.8f;  // α, docs/method.md A3
};

// The 12-D weighted feature of one frame: left/right wrist positions (m) then velocities (m/s).
void WristFeature(const FrameFeatures& features, const WristFeatureOptions& options, float out[kWristFeatureDims]);
// Every frame's feature, row-major (what the index is built over; BruteForceNearest's points).
std::vector<float> WristFeatures(const std::vector<FrameFeatures>& frames, const WristFeatureOptions& options = {});

class WristFeatureIndex {
 public:
  // Builds over `frames` (all clips' features, concatenated). FailedPrecondition when empty.
  absl::Status Build(const std::vector<FrameFeatures>& frames, const WristFeatureOptions& options = {});

  // The k nearest frames (rows of `frames`), nearest first, with their eq. 2 values.
  // InvalidArgument for k < 1 or a non-finite query.
  absl::StatusOr<std::vector<Neighbour>> Search(const float query[kWristFeatureDims], int k) const;

  int size() const { return tree_.size(); }
  size_t memory_bytes() const { return tree_.memory_bytes(); }

 private:
  KdTree tree_;
};

}  // namespace mocap

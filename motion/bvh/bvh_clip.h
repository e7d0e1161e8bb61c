// BvhClip: the content of a BVH file as read, before any interpretation.
#pragma once

#include <Eigen/Core>

#include "motion/skeleton/skeleton.h"

namespace mocap {

// Channel values row-major: one row per frame, columns in Skeleton channel order (see
// Skeleton::channel_start). Angles in degrees and lengths in file units, as in the file.
using ChannelMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

struct BvhClip {
  Skeleton skeleton;
  double frame_time = 0.0;  // seconds per frame
  ChannelMatrix channels;   // num_frames x skeleton.num_channels()

  int num_frames() const { return static_cast<int>(channels.rows()); }
  double frame_rate() const { return 1.0 / frame_time; }
};

}  // namespace mocap

// BvhClip: the content of a BVH file as read, before any interpretation.
#pragma once

#include <Eigen/Core>

#include "motion/skeleton/skeleton.h"

namespace mocap {

// Channel values row-major: one row per frame, columns in Skeleton channel order (see
// Skeleton::channel_start). Angles in degrees and lengths in file units, as in the file.
using ChannelMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// How the file's root position channels are read (motion/bvh/root_convention.h).
enum class RootPositionReading {
  kUnambiguous,         // root OFFSET zero (or no root position channels): every reader agrees
  kChannelsOnly,        // the channels are the root's position; its OFFSET is ignored (set to 0)
  kOffsetPlusChannels,  // root position = OFFSET + channels
};

struct BvhClip {
  Skeleton skeleton;
  double frame_time = 0.0;  // seconds per frame
  ChannelMatrix channels;   // num_frames x skeleton.num_channels()
  // As decided when the file was read; a clip made in code means OFFSET + channels.
  RootPositionReading root_reading = RootPositionReading::kUnambiguous;

  int num_frames() const { return static_cast<int>(channels.rows()); }
  double frame_rate() const { return 1.0 / frame_time; }
};

}  // namespace mocap

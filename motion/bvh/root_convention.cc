#include "motion/bvh/root_convention.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "motion/skeleton/forward_kinematics.h"
#include "motion/skeleton/local_motion.h"

namespace mocap {
namespace {

constexpr int kMaxSampledFrames = 64;

// Column of the root's position channel for each axis, or -1.
std::array<int, 3> RootPositionColumns(const Skeleton& skeleton) {
  std::array<int, 3> columns = {-1, -1, -1};
  if (skeleton.num_joints() == 0) return columns;
  const std::vector<ChannelType>& channels = skeleton.joint(0).channels;
  for (size_t c = 0; c < channels.size(); ++c) {
    if (!IsRotation(channels[c])) columns[ChannelAxis(channels[c])] = skeleton.channel_start(0) + static_cast<int>(c);
  }
  return columns;
}

float Median(std::vector<float> values) {
  if (values.empty()) return 0.0f;
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

// The 10th percentile: the body's lowest stretch, robust to a stray frame.
float LowPercentile(std::vector<float> values) {
  if (values.empty()) return 0.0f;
  const auto at = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 10);
  std::nth_element(values.begin(), at, values.end());
  return *at;
}

}  // namespace

RootPositionReading DecideRootPositionReading(const BvhClip& clip) {
  const Skeleton& skeleton = clip.skeleton;
  const std::array<int, 3> columns = RootPositionColumns(skeleton);
  if (skeleton.num_joints() == 0 || clip.num_frames() == 0) return RootPositionReading::kUnambiguous;
  Eigen::Vector3f driven_offset = Eigen::Vector3f::Zero();  // the part of the OFFSET readers disagree on
  for (int axis = 0; axis < 3; ++axis) {
    if (columns[axis] >= 0) driven_offset[axis] = skeleton.joint(0).offset[axis];
  }
  if (driven_offset.isZero()) return RootPositionReading::kUnambiguous;

  // The body with the channels alone, on evenly spaced frames.
  const int frames = std::min(clip.num_frames(), kMaxSampledFrames);
  ChannelMatrix sampled(frames, clip.channels.cols());
  for (int k = 0; k < frames; ++k) {
    sampled.row(k) = clip.channels.row(static_cast<int>(static_cast<long long>(k) * clip.num_frames() / frames));
  }
  std::vector<Joint> joints = skeleton.joints();
  joints[0].offset -= driven_offset;
  const Skeleton channels_only(std::move(joints));
  const GlobalPoses poses =
      ForwardKinematics(channels_only, MotionFromChannels(channels_only, sampled, clip.frame_time));
  // Values too large to pose (a hostile or broken file) give no evidence: keep the common reading.
  if (!poses.px.allFinite() || !poses.py.allFinite() || !poses.pz.allFinite()) {
    return RootPositionReading::kChannelsOnly;
  }

  // Up: the axis of the body's largest extent (a standing or moving body is taller than wide).
  int up = 1;
  float largest = -1.0f;
  std::array<Eigen::ArrayXXf const*, 3> axes = {&poses.px, &poses.py, &poses.pz};
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<float> extents(frames);
    for (int k = 0; k < frames; ++k) extents[k] = axes[axis]->row(k).maxCoeff() - axes[axis]->row(k).minCoeff();
    const float extent = Median(std::move(extents));
    if (extent > largest) {
      largest = extent;
      up = axis;
    }
  }
  // The lowest point, by the same axis taken either way up (a Z-down file is still a floor file),
  // where the body comes nearest the floor: a climb or a jump leaves it only for a while.
  std::vector<float> lowest(frames), highest(frames);
  for (int k = 0; k < frames; ++k) {
    lowest[k] = axes[up]->row(k).minCoeff();
    highest[k] = -axes[up]->row(k).maxCoeff();
  }
  const float low = LowPercentile(std::move(lowest)), high = -LowPercentile(std::move(highest));
  const float shift = driven_offset[up];
  // Distance of the nearer end of the body to the floor, under each reading.
  const float alone = std::min(std::abs(low), std::abs(high));
  const float summed = std::min(std::abs(low + shift), std::abs(high + shift));
  return summed < alone ? RootPositionReading::kOffsetPlusChannels : RootPositionReading::kChannelsOnly;
}

void NormaliseRootPosition(BvhClip& clip) {
  clip.root_reading = DecideRootPositionReading(clip);
  if (clip.root_reading != RootPositionReading::kChannelsOnly) return;
  const std::array<int, 3> columns = RootPositionColumns(clip.skeleton);
  std::vector<Joint> joints = clip.skeleton.joints();
  for (int axis = 0; axis < 3; ++axis) {
    if (columns[axis] >= 0) joints[0].offset[axis] = 0.0f;
  }
  clip.skeleton = Skeleton(std::move(joints));
}

namespace {

// A non-root position channel whose value never changes: written as the joint's OFFSET instead.
bool ConstantChannel(const BvhClip& clip, int column) {
  return clip.num_frames() == 0 || (clip.channels.col(column).array() == clip.channels(0, column)).all();
}

}  // namespace

bool ReadersAgreeOn(const BvhClip& clip) {
  const Skeleton& skeleton = clip.skeleton;
  for (int j = 0; j < skeleton.num_joints(); ++j) {
    const Joint& joint = skeleton.joint(j);
    bool has_position = false, all_constant = true;
    for (size_t c = 0; c < joint.channels.size(); ++c) {
      if (IsRotation(joint.channels[c])) continue;
      if (joint.offset[ChannelAxis(joint.channels[c])] != 0.0f) return false;
      has_position = true;
      all_constant &= ConstantChannel(clip, skeleton.channel_start(j) + static_cast<int>(c));
    }
    if (j > 0 && has_position && all_constant) return false;
  }
  return true;
}

bool MakeReadersAgree(BvhClip& clip) {
  if (clip.skeleton.num_joints() == 0 || ReadersAgreeOn(clip)) return false;
  const Skeleton& skeleton = clip.skeleton;
  std::vector<Joint> joints = skeleton.joints();
  std::vector<int> kept_columns;  // old channel columns, in the new order
  for (int j = 0; j < skeleton.num_joints(); ++j) {
    Joint& joint = joints[j];
    joint.channels.clear();
    const std::vector<ChannelType>& channels = skeleton.joint(j).channels;
    // A joint's position channels go together: Blender reads a missing one as 0, not as the OFFSET.
    bool all_constant = true;
    for (size_t c = 0; c < channels.size(); ++c) {
      if (!IsRotation(channels[c]))
        all_constant &= ConstantChannel(clip, skeleton.channel_start(j) + static_cast<int>(c));
    }
    for (size_t c = 0; c < channels.size(); ++c) {
      const int column = skeleton.channel_start(j) + static_cast<int>(c);
      const int axis = ChannelAxis(channels[c]);
      if (!IsRotation(channels[c])) {
        if (j == 0) {
          // The root: its OFFSET goes into the channels (Blender ignores it, the others add it).
          clip.channels.col(column).array() += joint.offset[axis];
          joint.offset[axis] = 0.0f;
        } else if (all_constant) {
          // A fixed translation: the OFFSET, on which every reader agrees, without the channel.
          if (clip.num_frames() > 0) joint.offset[axis] = clip.channels(0, column);
          continue;
        } else {
          // An animated translation: the channels replace the OFFSET for Blender and this reader,
          // three.js adds the OFFSET to them; a zero OFFSET makes them agree.
          joint.offset[axis] = 0.0f;
        }
      }
      joint.channels.push_back(channels[c]);
      kept_columns.push_back(column);
    }
  }
  ChannelMatrix channels(clip.num_frames(), static_cast<Eigen::Index>(kept_columns.size()));
  for (size_t k = 0; k < kept_columns.size(); ++k)
    channels.col(static_cast<Eigen::Index>(k)) = clip.channels.col(kept_columns[k]);
  clip.channels = std::move(channels);
  clip.skeleton = Skeleton(std::move(joints));
  return true;
}

}  // namespace mocap

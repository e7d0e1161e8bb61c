// LocalMotion: joint-local transforms over frames, structure-of-arrays so that per-joint loops run
// over contiguous frames (vectorisable forward kinematics).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "motion/bvh/bvh_clip.h"
#include "motion/skeleton/skeleton.h"

namespace mocap {

// Each array is num_frames x num_joints, column j = joint j over all frames. Rotations are unit
// quaternions (w, x, y, z) mapping the joint's frame into its parent's; translations are the joint
// origin in the parent frame (OFFSET or position channels), in whatever length unit was given.
struct LocalMotion {
  double frame_time = 1.0 / 30.0;
  Eigen::ArrayXXf qw, qx, qy, qz;
  Eigen::ArrayXXf tx, ty, tz;

  int num_frames() const { return static_cast<int>(qw.rows()); }
  int num_joints() const { return static_cast<int>(qw.cols()); }
  void Resize(int frames, int joints);
  Eigen::Quaternionf rotation(int frame, int joint) const {
    return Eigen::Quaternionf(qw(frame, joint), qx(frame, joint), qy(frame, joint), qz(frame, joint));
  }
  Eigen::Vector3f translation(int frame, int joint) const {
    return Eigen::Vector3f(tx(frame, joint), ty(frame, joint), tz(frame, joint));
  }
  void SetRotation(int frame, int joint, const Eigen::Quaternionf& q);
  void SetTranslation(int frame, int joint, const Eigen::Vector3f& t);
};

// Interprets BVH channels: rotation channels compose in file order (intrinsic, R = R1·R2·R3);
// on the root, translation = OFFSET + position channels; on other joints a position channel
// replaces that component of the OFFSET (shared/data/README).
LocalMotion MotionFromChannels(const Skeleton& skeleton, const ChannelMatrix& channels, double frame_time);

// The inverse: Euler angles in each joint's channel order, positions as above. Joints with fewer
// than three rotation channels keep only the rotation about their axes.
ChannelMatrix ChannelsFromMotion(const Skeleton& skeleton, const LocalMotion& motion);

// Resamples to `target_frame_time` (slerp for rotations, linear for translations). Output frame k
// is at time k * target_frame_time, for every such time within the clip.
LocalMotion Resample(const LocalMotion& motion, double target_frame_time);

// Multiplies every translation by `factor` (unit conversion).
void ScaleTranslations(LocalMotion& motion, float factor);

// Applies a world rotation to the whole motion (pre-multiplies the root transform).
void RotateWorld(LocalMotion& motion, const Eigen::Quaternionf& rotation);

}  // namespace mocap

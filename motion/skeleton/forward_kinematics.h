// Forward kinematics over whole clips, vectorised over frames.
#pragma once

#include <Eigen/Core>

#include "motion/skeleton/local_motion.h"
#include "motion/skeleton/skeleton.h"

namespace mocap {

// World transforms of every joint at every frame; arrays are num_frames x num_joints like
// LocalMotion. Positions are in the motion's length unit.
struct GlobalPoses {
  Eigen::ArrayXXf px, py, pz;
  Eigen::ArrayXXf qw, qx, qy, qz;

  int num_frames() const { return static_cast<int>(px.rows()); }
  int num_joints() const { return static_cast<int>(px.cols()); }
  Eigen::Vector3f position(int frame, int joint) const {
    return Eigen::Vector3f(px(frame, joint), py(frame, joint), pz(frame, joint));
  }
  Eigen::Quaternionf rotation(int frame, int joint) const {
    return Eigen::Quaternionf(qw(frame, joint), qx(frame, joint), qy(frame, joint), qz(frame, joint));
  }
};

// `parents[j]` < j for every non-root joint (Skeleton's invariant).
GlobalPoses ForwardKinematics(const Skeleton& skeleton, const LocalMotion& motion);

// Rest pose: every rotation zero, translations from OFFSETs; one frame.
LocalMotion RestMotion(const Skeleton& skeleton);

// Length of each joint's bone (|local translation|) averaged over frames; 0 for the root.
Eigen::VectorXf BoneLengths(const LocalMotion& motion);

}  // namespace mocap

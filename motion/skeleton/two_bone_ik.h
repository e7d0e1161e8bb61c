// Analytic two-bone inverse kinematics (hip-knee-ankle, shoulder-elbow-wrist) on world positions,
// shared by the footskate cleanup (docs/method.md A7) and the retargeting onto a caller's rig.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace mocap {

// World rotations that move the end `c` of the chain a -> b -> c onto `target`: first `middle_turn`
// about b (changing the interior angle so that |c - a| becomes the target's distance, clamped to
// what the bones can reach), then `root_turn` about a (swinging the bent chain onto the line to
// the target). Applied to the world transforms: every joint below b turns by root_turn ·
// middle_turn, joints from a to b by root_turn. `bend_axis` is used when the chain is straight
// (no bend plane of its own); it need not be unit length.
struct TwoBoneTurns {
  Eigen::Quaternionf root_turn = Eigen::Quaternionf::Identity();
  Eigen::Quaternionf middle_turn = Eigen::Quaternionf::Identity();
};
// Identity turns when a bone has (near) zero length.
TwoBoneTurns SolveTwoBoneIk(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c,
                            const Eigen::Vector3f& target, const Eigen::Vector3f& bend_axis);

}  // namespace mocap

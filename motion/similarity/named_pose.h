// A pose given as named joint positions with its landmarks named (what an app sends: no rig
// analysis), turned into body points comparable with any rig's (docs/method.md B3–B4).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "absl/status/statusor.h"
#include "motion/similarity/pose_index.h"

namespace mocap {

struct NamedPoseJoint {
  std::string name;
  std::string parent;        // a joint listed earlier; empty for the root
  Eigen::Vector3f position;  // world position, any length unit
};

struct NamedPose {
  std::vector<NamedPoseJoint> joints;  // parents before children
  std::string up = "+Y";               // "+Y", "-Y", "+X", "-X", "+Z" or "-Z"; empty: +Y
  // Joint names of the landmarks.
  std::string pelvis, head, left_wrist, right_wrist, left_ankle, right_ankle;
  // Optional (empty: found by length, BodyChains): where each limb bends and where its upper long
  // bone starts (past a clavicle or hip offset). A shoulder (hip) needs its elbow (knee).
  std::string left_elbow, right_elbow, left_knee, right_knee;
  std::string left_shoulder, right_shoulder, left_hip, right_hip;
};

// Upper bound on NamedPose::joints (the skeleton's own limit).
int MaxNamedPoseJoints();

// One-frame points of the pose. InvalidArgument naming the joint or landmark when the pose is
// not a valid body: a parent not listed before its child, a non-finite position, an unknown up
// axis, a landmark naming no joint, landmarks that do not form a body or an elbow, knee, shoulder
// or hip outside its limb (ChainsFromLandmarks).
absl::StatusOr<ClipPoints> NamedPosePoints(const NamedPose& pose, const BodyPointOptions& options);

}  // namespace mocap

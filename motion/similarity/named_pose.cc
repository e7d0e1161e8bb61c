#include "motion/similarity/named_pose.h"

#include <tuple>

#include <Eigen/Geometry>

#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"

namespace mocap {
namespace {

absl::StatusOr<Eigen::Vector3f> UpVector(const std::string& up) {
  if (up.empty()) return Eigen::Vector3f::UnitY();
  if (up.size() != 2 || (up[0] != '+' && up[0] != '-') || up[1] < 'X' || up[1] > 'Z') {
    return absl::InvalidArgumentError("pose 'up' must be one of +X, -X, +Y, -Y, +Z, -Z");
  }
  Eigen::Vector3f vector = Eigen::Vector3f::Zero();
  vector[up[1] - 'X'] = up[0] == '+' ? 1.0f : -1.0f;
  return vector;
}

}  // namespace

int MaxNamedPoseJoints() { return Skeleton::kMaxJoints; }

absl::StatusOr<ClipPoints> NamedPosePoints(const NamedPose& pose, const BodyPointOptions& options) {
  if (pose.joints.empty()) return absl::InvalidArgumentError("pose has no joints");
  if (static_cast<int>(pose.joints.size()) > MaxNamedPoseJoints()) {
    return absl::InvalidArgumentError(
        StrCat("pose has ", pose.joints.size(), " joints; at most ", MaxNamedPoseJoints()));
  }
  std::vector<Joint> joints;
  for (const NamedPoseJoint& entry : pose.joints) {
    Joint joint;
    joint.name = entry.name;
    if (!entry.parent.empty()) {
      for (size_t i = 0; i < joints.size(); ++i) {
        if (joints[i].name == entry.parent) joint.parent = static_cast<int>(i);
      }
      if (joint.parent < 0) {
        return absl::InvalidArgumentError(
            StrCat("pose joint '", entry.name, "': parent '", entry.parent, "' must be listed before it"));
      }
    }
    if (!entry.position.allFinite())
      return absl::InvalidArgumentError(StrCat("pose joint '", entry.name, "' is not finite"));
    joints.push_back(std::move(joint));
  }
  Skeleton skeleton(std::move(joints));
  if (absl::Status status = skeleton.Validate(); !status.ok()) {
    return absl::InvalidArgumentError(StrCat("pose: ", status.message()));
  }
  MOCAP_ASSIGN_OR_RETURN(const Eigen::Vector3f up, UpVector(pose.up));
  const Eigen::Quaternionf to_y_up = Eigen::Quaternionf::FromTwoVectors(up, Eigen::Vector3f::UnitY());
  GlobalPoses poses;
  for (Eigen::ArrayXXf* a : {&poses.px, &poses.py, &poses.pz, &poses.qw, &poses.qx, &poses.qy, &poses.qz}) {
    a->setZero(1, skeleton.num_joints());
  }
  poses.qw.setOnes();
  for (int j = 0; j < skeleton.num_joints(); ++j) {
    const Eigen::Vector3f p = to_y_up * pose.joints[j].position;  // the unit does not matter: points are in leg lengths
    poses.px(0, j) = p.x();
    poses.py(0, j) = p.y();
    poses.pz(0, j) = p.z();
  }
  auto landmark = [&](const char* key, const std::string& name) -> absl::StatusOr<int> {
    const int joint = skeleton.Find(name);
    if (joint < 0) return absl::InvalidArgumentError(StrCat("pose landmark '", key, "' names no joint"));
    return joint;
  };
  BodyLandmarks landmarks;
  MOCAP_ASSIGN_OR_RETURN(landmarks.pelvis, landmark("pelvis", pose.pelvis));
  MOCAP_ASSIGN_OR_RETURN(landmarks.head, landmark("head", pose.head));
  MOCAP_ASSIGN_OR_RETURN(landmarks.left_wrist, landmark("left_wrist", pose.left_wrist));
  MOCAP_ASSIGN_OR_RETURN(landmarks.right_wrist, landmark("right_wrist", pose.right_wrist));
  MOCAP_ASSIGN_OR_RETURN(landmarks.left_ankle, landmark("left_ankle", pose.left_ankle));
  MOCAP_ASSIGN_OR_RETURN(landmarks.right_ankle, landmark("right_ankle", pose.right_ankle));
  for (auto [key, name, joint] : {std::tuple{"left_elbow", &pose.left_elbow, &landmarks.left_elbow},
                                  std::tuple{"right_elbow", &pose.right_elbow, &landmarks.right_elbow},
                                  std::tuple{"left_knee", &pose.left_knee, &landmarks.left_knee},
                                  std::tuple{"right_knee", &pose.right_knee, &landmarks.right_knee},
                                  std::tuple{"left_shoulder", &pose.left_shoulder, &landmarks.left_shoulder},
                                  std::tuple{"right_shoulder", &pose.right_shoulder, &landmarks.right_shoulder},
                                  std::tuple{"left_hip", &pose.left_hip, &landmarks.left_hip},
                                  std::tuple{"right_hip", &pose.right_hip, &landmarks.right_hip}}) {
    if (name->empty()) continue;
    MOCAP_ASSIGN_OR_RETURN(*joint, landmark(key, *name));
  }
  MOCAP_ASSIGN_OR_RETURN(BodyChains chains, ChainsFromLandmarks(skeleton, landmarks));
  return MakeClipPoints(poses, chains, options);
}

}  // namespace mocap

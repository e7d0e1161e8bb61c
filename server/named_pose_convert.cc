#include "server/named_pose_convert.h"

namespace mocap {

NamedPose FromProto(const v1::NamedPose& pose) {
  NamedPose out;
  for (const v1::NamedJoint& joint : pose.joints()) {
    out.joints.push_back({joint.name(), joint.parent(),
                          Eigen::Vector3f(joint.position().x(), joint.position().y(), joint.position().z())});
  }
  out.up = pose.up();
  const v1::NamedLandmarks& l = pose.landmarks();
  out.pelvis = l.pelvis();
  out.head = l.head();
  out.left_wrist = l.left_wrist();
  out.right_wrist = l.right_wrist();
  out.left_ankle = l.left_ankle();
  out.right_ankle = l.right_ankle();
  out.left_elbow = l.left_elbow();
  out.right_elbow = l.right_elbow();
  out.left_knee = l.left_knee();
  out.right_knee = l.right_knee();
  out.left_shoulder = l.left_shoulder();
  out.right_shoulder = l.right_shoulder();
  out.left_hip = l.left_hip();
  out.right_hip = l.right_hip();
  return out;
}

void ToProto(const NamedPose& pose, v1::NamedPose* out) {
  for (const NamedPoseJoint& joint : pose.joints) {
    v1::NamedJoint* named = out->add_joints();
    named->set_name(joint.name);
    named->set_parent(joint.parent);
    named->mutable_position()->set_x(joint.position.x());
    named->mutable_position()->set_y(joint.position.y());
    named->mutable_position()->set_z(joint.position.z());
  }
  out->set_up(pose.up);
  v1::NamedLandmarks* l = out->mutable_landmarks();
  l->set_pelvis(pose.pelvis);
  l->set_head(pose.head);
  l->set_left_wrist(pose.left_wrist);
  l->set_right_wrist(pose.right_wrist);
  l->set_left_ankle(pose.left_ankle);
  l->set_right_ankle(pose.right_ankle);
  l->set_left_elbow(pose.left_elbow);
  l->set_right_elbow(pose.right_elbow);
  l->set_left_knee(pose.left_knee);
  l->set_right_knee(pose.right_knee);
  l->set_left_shoulder(pose.left_shoulder);
  l->set_right_shoulder(pose.right_shoulder);
  l->set_left_hip(pose.left_hip);
  l->set_right_hip(pose.right_hip);
}

}  // namespace mocap

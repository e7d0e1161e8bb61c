#include "motion/reconstruct/body_model.h"

#include <algorithm>
#include <limits>
#include <optional>

#include "motion/core/rotation_vector.h"
#include "motion/core/str_cat.h"
#include "motion/reconstruct/hand_floor.h"

namespace mocap {

absl::StatusOr<BodyModel> BodyModel::Create(const RigModel& rig, const Skeleton& skeleton,
                                            const std::vector<int>& pose_joints) {
  if (!skeleton.SameRigAs(rig.skeleton))
    return absl::InvalidArgumentError("body model skeleton is not the rig's hierarchy");
  const int joints = skeleton.num_joints();
  if (static_cast<int>(rig.reference_rotations.size()) != joints) {
    return absl::InvalidArgumentError("rig has no reference rotation per joint");
  }
  BodyModel model;
  model.rig_ = rig;
  model.skeleton_ = skeleton;
  model.pose_joints_ = pose_joints;
  model.pose_slot_.assign(joints, -1);
  const BodyLandmarks& l = rig.topology.landmarks;
  std::vector<bool> on_chain(joints, false);
  std::vector<int> chain;
  for (int j = l.pelvis; j >= 0; j = skeleton.parent(j)) {
    on_chain[j] = true;
    chain.push_back(j);
  }
  for (size_t i = 0; i < pose_joints.size(); ++i) {
    const int j = pose_joints[i];
    if (j < 0 || j >= joints || on_chain[j]) {
      return absl::InvalidArgumentError(StrCat("pose joint ", j, " is outside the rig or on the pelvis chain"));
    }
    model.pose_slot_[j] = static_cast<int>(i);
  }
  for (int j = 0; j < joints; ++j) {
    model.reference_.push_back(rig.reference_rotations[j].cast<double>().normalized());
    model.offset_.push_back(skeleton.joint(j).offset.cast<double>());
  }
  // K = L(c1)·…·L(pelvis) with the chain at its reference rotations (the root excluded).
  std::reverse(chain.begin(), chain.end());
  for (size_t i = 1; i < chain.size(); ++i) {
    const int j = chain[i];
    model.chain_translation_ += model.chain_rotation_ * model.offset_[j];
    model.chain_rotation_ = model.chain_rotation_ * model.reference_[j];
  }
  model.control_landmarks_ = {l.left_wrist, l.right_wrist, l.left_ankle, l.right_ankle};
  // A joint's centre lies a limb's radius above the ground at the lowest; the head's, half a head.
  for (const auto& [joint, lowest] : {std::pair{l.pelvis, kLowestJointHeight},
                                      {l.head, kLowestHeadHeight},
                                      {l.left_shoulder, kLowestJointHeight},
                                      {l.right_shoulder, kLowestJointHeight},
                                      {l.left_elbow, kLowestJointHeight},
                                      {l.right_elbow, kLowestJointHeight},
                                      {l.left_hip, kLowestJointHeight},
                                      {l.right_hip, kLowestJointHeight},
                                      {l.left_knee, kLowestJointHeight},
                                      {l.right_knee, kLowestJointHeight}}) {
    if (joint < 0 ||
        std::find(model.floor_joints_.begin(), model.floor_joints_.end(), joint) != model.floor_joints_.end())
      continue;
    model.floor_joints_.push_back(joint);
    model.floor_heights_.push_back(lowest);
  }
  std::vector<bool> needed(joints, false);
  for (int landmark : model.control_landmarks_) {
    for (int j = landmark; j >= 0; j = skeleton.parent(j)) needed[j] = true;
  }
  for (int joint : model.floor_joints_) {
    for (int j = joint; j >= 0; j = skeleton.parent(j)) needed[j] = true;
  }
  for (int j = 0; j < joints; ++j) {
    if (needed[j]) model.control_joints_.push_back(j);
  }
  return model;
}

void BodyModel::RootFromPelvis(const Eigen::Quaterniond& pelvis_rotation, const Eigen::Vector3d& pelvis_position,
                               Eigen::Quaterniond* root_rotation, Eigen::Vector3d* root_position) const {
  *root_rotation = pelvis_rotation * chain_rotation_.conjugate();
  *root_position = pelvis_position - *root_rotation * chain_translation_;
}

void BodyModel::ControlPoints(const Eigen::Quaterniond& pelvis_rotation, const Eigen::Vector3d& pelvis_position,
                              const double* q, std::array<Eigen::Vector3d, kNumControlPoints>* out,
                              double* clearances) const {
  // Small fixed-size work per call (the solver calls this ~100 times per frame): world transforms
  // of the needed joints only, in a stack buffer when the rig is small enough.
  constexpr int kStack = 128;
  Eigen::Quaterniond stack_rotations[kStack];
  Eigen::Vector3d stack_positions[kStack];
  std::vector<Eigen::Quaterniond> heap_rotations;
  std::vector<Eigen::Vector3d> heap_positions;
  Eigen::Quaterniond* rotation = stack_rotations;
  Eigen::Vector3d* position = stack_positions;
  if (skeleton_.num_joints() > kStack) {
    heap_rotations.resize(skeleton_.num_joints());
    heap_positions.resize(skeleton_.num_joints());
    rotation = heap_rotations.data();
    position = heap_positions.data();
  }
  for (int j : control_joints_) {
    const int parent = skeleton_.parent(j);
    if (parent < 0) {
      RootFromPelvis(pelvis_rotation, pelvis_position, &rotation[j], &position[j]);
      continue;
    }
    const int slot = pose_slot_[j];
    const Eigen::Quaterniond local =
        slot < 0 ? reference_[j] : reference_[j] * FromRotationVector(Eigen::Map<const Eigen::Vector3d>(q + 3 * slot));
    position[j] = position[parent] + rotation[parent] * offset_[j];
    rotation[j] = rotation[parent] * local;
  }
  for (int c = 0; c < kNumControlPoints; ++c) (*out)[c] = position[control_landmarks_[c]];
  if (clearances) {
    for (size_t f = 0; f < floor_joints_.size(); ++f)
      clearances[f] = position[floor_joints_[f]].y() - floor_heights_[f];
  }
}

float BodyModel::FloorClearance(std::span<const Eigen::Vector3f> world_positions) const {
  float clearance = std::numeric_limits<float>::infinity();
  for (size_t f = 0; f < floor_joints_.size(); ++f) {
    clearance = std::min(clearance, world_positions[floor_joints_[f]].y() - static_cast<float>(floor_heights_[f]));
  }
  return clearance;
}

BodyPose BodyModel::Pose(const Eigen::Quaternionf& pelvis_rotation, const Eigen::Vector3f& pelvis_position,
                         const float* q) const {
  Eigen::Quaterniond root_rotation;
  Eigen::Vector3d root_position;
  RootFromPelvis(pelvis_rotation.cast<double>().normalized(), pelvis_position.cast<double>(), &root_rotation,
                 &root_position);
  BodyPose pose;
  pose.root_position = root_position.cast<float>();
  pose.rotations.resize(skeleton_.num_joints());
  pose.rotations[0] = root_rotation.cast<float>();
  for (int j = 1; j < skeleton_.num_joints(); ++j) {
    const int slot = pose_slot_[j];
    const Eigen::Quaterniond local =
        slot < 0 ? reference_[j]
                 : reference_[j] * FromRotationVector(Eigen::Vector3d(q[3 * slot], q[3 * slot + 1], q[3 * slot + 2]));
    pose.rotations[j] = local.cast<float>();
  }
  return pose;
}

void BodyModel::WorldTransforms(const BodyPose& pose, std::vector<Eigen::Quaternionf>* rotations,
                                std::vector<Eigen::Vector3f>* positions) const {
  const int joints = skeleton_.num_joints();
  rotations->resize(joints);
  positions->resize(joints);
  (*rotations)[0] = pose.rotations[0];
  (*positions)[0] = pose.root_position;
  for (int j = 1; j < joints; ++j) {
    const int parent = skeleton_.parent(j);
    (*positions)[j] = (*positions)[parent] + (*rotations)[parent] * offset_[j].cast<float>();
    (*rotations)[j] = (*rotations)[parent] * pose.rotations[j];
  }
}

LocalMotion BodyModel::ToLocalMotion(const std::vector<BodyPose>& poses, double frame_time) const {
  LocalMotion motion;
  motion.frame_time = frame_time;
  motion.Resize(static_cast<int>(poses.size()), skeleton_.num_joints());
  for (int f = 0; f < static_cast<int>(poses.size()); ++f) {
    for (int j = 0; j < skeleton_.num_joints(); ++j) {
      motion.SetRotation(f, j, poses[f].rotations[j]);
      motion.SetTranslation(f, j, j == 0 ? poses[f].root_position : Eigen::Vector3f(offset_[j].cast<float>()));
    }
  }
  return motion;
}

float RestPoseHeight(const BodyModel& body) {
  const Skeleton& skeleton = body.skeleton();
  // Along the zero-rotation pose's own up axis (pelvis → head), which is not the world's on many
  // rigs (Bandai's rest pose lies along +X, Z-up hierarchies stand along +Z).
  const BodyTopology& topology = body.rig().topology;
  Eigen::Vector3f up = Eigen::Vector3f::Zero();
  up[topology.rest_up_axis] = static_cast<float>(topology.rest_up_sign);
  std::vector<Eigen::Vector3f> position(skeleton.num_joints());
  float low = 0.0f, high = 0.0f;
  for (int j = 0; j < skeleton.num_joints(); ++j) {
    const int parent = skeleton.parent(j);
    position[j] = parent < 0 ? Eigen::Vector3f::Zero() : Eigen::Vector3f(position[parent] + skeleton.joint(j).offset);
    std::array<std::optional<Eigen::Vector3f>, 2> points = {position[j], std::nullopt};
    if (skeleton.joint(j).end_site) points[1] = position[j] + *skeleton.joint(j).end_site;
    for (const auto& point : points) {
      if (!point) continue;
      const float y = up.dot(*point);
      low = std::min(low, y);
      high = std::max(high, y);
    }
  }
  return high - low;
}

namespace {

// Every joint's position with every joint at its zero rotation.
std::vector<Eigen::Vector3f> RestPositions(const BodyModel& body) {
  BodyPose rest;
  rest.rotations.assign(body.skeleton().num_joints(), Eigen::Quaternionf::Identity());
  std::vector<Eigen::Quaternionf> rotations;
  std::vector<Eigen::Vector3f> positions;
  body.WorldTransforms(rest, &rotations, &positions);
  return positions;
}

// Both limbs' lengths (root → middle → end landmark, left and right), measured on the body's
// zero-rotation pose; nullopt when a landmark is missing.
std::optional<float> LimbsLength(const BodyModel& body, const std::array<std::array<int, 3>, 2>& limbs,
                                 std::vector<Eigen::Vector3f>* positions) {
  *positions = RestPositions(body);
  float length = 0.0f;
  for (const auto& [root, middle, end] : limbs) {
    if (root < 0 || middle < 0 || end < 0) return std::nullopt;
    length += ((*positions)[root] - (*positions)[middle]).norm() + ((*positions)[middle] - (*positions)[end]).norm();
  }
  return length;
}

}  // namespace

float EstimatedStature(const BodyModel& body) {
  const BodyLandmarks& l = body.rig().topology.landmarks;
  std::vector<Eigen::Vector3f> positions;
  const std::optional<float> legs = LimbsLength(
      body, {std::array<int, 3>{l.left_hip, l.left_knee, l.left_ankle}, {l.right_hip, l.right_knee, l.right_ankle}},
      &positions);
  return legs ? static_cast<float>(0.5 * *legs / kLegShareOfStature) : 0.0f;
}

float WristSpan(const BodyModel& body) {
  const BodyLandmarks& l = body.rig().topology.landmarks;
  std::vector<Eigen::Vector3f> positions;
  const std::optional<float> arms = LimbsLength(body,
                                                {std::array<int, 3>{l.left_shoulder, l.left_elbow, l.left_wrist},
                                                 {l.right_shoulder, l.right_elbow, l.right_wrist}},
                                                &positions);
  return arms ? *arms + (positions[l.left_shoulder] - positions[l.right_shoulder]).norm() : 0.0f;
}

float ForearmLength(const BodyModel& body) {
  const BodyLandmarks& l = body.rig().topology.landmarks;
  if (l.left_elbow < 0 || l.left_wrist < 0 || l.right_elbow < 0 || l.right_wrist < 0) return 0.0f;
  const std::vector<Eigen::Vector3f> positions = RestPositions(body);
  return 0.5f * ((positions[l.left_wrist] - positions[l.left_elbow]).norm() +
                 (positions[l.right_wrist] - positions[l.right_elbow]).norm());
}

}  // namespace mocap

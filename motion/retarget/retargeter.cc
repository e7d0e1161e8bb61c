#include "motion/retarget/retargeter.h"

#include <algorithm>
#include <cmath>

#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"
#include "motion/skeleton/two_bone_ik.h"

namespace mocap {
namespace {

constexpr int kSpine = static_cast<int>(BodyGroup::kSpine);
constexpr int kHead = static_cast<int>(BodyGroup::kHead);

// Sections of a chain between anchors, as [first, last] index pairs.
std::vector<std::pair<int, int>> Sections(const RetargetRig& rig, int group) {
  const int end = static_cast<int>(rig.chains.joints[group].size()) - 1;
  if (group == kSpine || group == kHead) return {{0, end}};
  const LimbAnchors& a = rig.anchors[group];
  return {{0, a.root}, {a.root, a.middle}, {a.middle, end}};
}

// Rest lengths from the chain's first joint to each of its joints.
std::vector<float> CumulativeLengths(const RetargetRig& rig, int group) {
  const std::vector<int>& chain = rig.chains.joints[group];
  std::vector<float> along(chain.size(), 0.0f);
  for (size_t i = 1; i < chain.size(); ++i) {
    along[i] = along[i - 1] + (rig.rest_positions[chain[i]] - rig.rest_positions[chain[i - 1]]).norm();
  }
  return along;
}

// Rest frame of a bone: its direction, then the body's forward (its up for bones along forward).
Eigen::Matrix3f BoneFrame(const Eigen::Vector3f& direction, const Eigen::Vector3f& secondary) {
  Eigen::Matrix3f frame;
  frame.col(0) = direction;
  frame.col(1) = (secondary - direction * direction.dot(secondary)).normalized();
  frame.col(2) = frame.col(0).cross(frame.col(1));
  return frame;
}

// The rotation taking the target's rest bone onto the source's, each with its body's forward
// (or up) on the same side: the rest poses' difference for this bone, without a twist flip.
Eigen::Quaternionf RestAlignment(const Eigen::Vector3f& target_direction, const RetargetRig& target,
                                 const Eigen::Vector3f& source_direction, const RetargetRig& source) {
  const bool along_forward = std::abs(target_direction.dot(target.rest_body_frame.col(2))) > 0.9f ||
                             std::abs(source_direction.dot(source.rest_body_frame.col(2))) > 0.9f;
  const int secondary = along_forward ? 1 : 2;
  const Eigen::Matrix3f t = BoneFrame(target_direction, target.rest_body_frame.col(secondary));
  const Eigen::Matrix3f s = BoneFrame(source_direction, source.rest_body_frame.col(secondary));
  return Eigen::Quaternionf(Eigen::Matrix3f(s * t.transpose())).normalized();
}

int LimbRoot(const RetargetRig& rig, BodyGroup limb) {
  const int g = static_cast<int>(limb);
  return rig.chains.joints[g][rig.anchors[g].root];
}

// Direction a chain's end joint points in the rest pose: to its group's limb end when that is
// away from it (hand, foot, top of the head), else along the chain's last bone.
Eigen::Vector3f EndDirection(const RetargetRig& rig, int group) {
  const std::vector<int>& chain = rig.chains.joints[group];
  const int end = chain.back();
  const Eigen::Vector3f beyond = rig.rest_positions[rig.topology.group_end[group]] - rig.rest_positions[end];
  if (beyond.norm() > 0.02f * rig.leg_length) return beyond.normalized();
  if (chain.size() >= 2) {
    const Eigen::Vector3f last = rig.rest_positions[end] - rig.rest_positions[chain[chain.size() - 2]];
    if (last.norm() > 1e-6f) return last.normalized();
  }
  return rig.rest_body_frame.col(1);
}

Eigen::Matrix3f PelvisFrame(const RetargetRig& rig, const std::vector<Eigen::Vector3f>& p) {
  const int pelvis = rig.topology.landmarks.pelvis;
  Eigen::Vector3f up = p[rig.chains.joints[kSpine].back()] - p[pelvis];
  if (up.norm() < 0.05f * rig.leg_length) up = p[rig.topology.landmarks.head] - p[pelvis];
  return FrameFromUpLeft(up, p[LimbRoot(rig, BodyGroup::kLeftLeg)] - p[LimbRoot(rig, BodyGroup::kRightLeg)]);
}

Eigen::Matrix3f ChestFrame(const RetargetRig& rig, const std::vector<Eigen::Vector3f>& p) {
  return FrameFromUpLeft(p[rig.topology.landmarks.head] - p[rig.chains.joints[kSpine].back()],
                         p[LimbRoot(rig, BodyGroup::kLeftArm)] - p[LimbRoot(rig, BodyGroup::kRightArm)]);
}

}  // namespace

Eigen::Matrix3f FrameFromUpLeft(const Eigen::Vector3f& up, const Eigen::Vector3f& left) {
  Eigen::Matrix3f frame;
  const Eigen::Vector3f u = up.normalized();
  Eigen::Vector3f l = left - u * u.dot(left);
  if (l.norm() < 1e-6f) l = u.unitOrthogonal();
  frame.col(0) = l.normalized();
  frame.col(1) = u;
  frame.col(2) = frame.col(0).cross(u);
  return frame;
}

absl::StatusOr<Retargeter> Retargeter::Create(RetargetRig source, RetargetRig target) {
  Retargeter retargeter;
  retargeter.source_ = std::move(source);
  retargeter.target_ = std::move(target);
  MOCAP_RETURN_IF_ERROR(retargeter.MapJoints());
  const int joints = retargeter.target_.skeleton.num_joints();
  retargeter.world_rotations_.resize(joints);
  retargeter.world_positions_.resize(joints);
  return retargeter;
}

absl::Status Retargeter::MapJoints() {
  const RetargetRig& s = source_;
  const RetargetRig& t = target_;
  scale_ = t.leg_length / s.leg_length;
  maps_.assign(t.skeleton.num_joints(), JointMap{});
  const int pelvis = t.topology.landmarks.pelvis;
  pelvis_path_.clear();
  for (int j = pelvis; j > 0; j = t.skeleton.parent(j)) pelvis_path_.insert(pelvis_path_.begin(), j);

  for (int group = 0; group < kNumBodyGroups; ++group) {
    const std::vector<int>& chain = t.chains.joints[group];
    const std::vector<int>& source_chain = s.chains.joints[group];
    const std::vector<float> along = CumulativeLengths(t, group), source_along = CumulativeLengths(s, group);
    const auto sections = Sections(t, group), source_sections = Sections(s, group);
    // The source point at the fraction of section `k` where target chain index `i` lies.
    auto source_point = [&](size_t k, int i) {
      const auto [first, last] = sections[k];
      const auto [source_first, source_last] = source_sections[k];
      const float length = along[last] - along[first];
      const float fraction = length > 1e-6f ? (along[i] - along[first]) / length : 0.0f;
      const float x = source_along[source_first] + fraction * (source_along[source_last] - source_along[source_first]);
      int a = source_first;
      while (a + 1 < source_last && source_along[a + 1] <= x) ++a;
      const int b = std::min(a + 1, source_last);
      const float span = source_along[b] - source_along[a];
      return ChainPoint{source_chain[a], source_chain[b],
                        span > 1e-6f ? std::clamp((x - source_along[a]) / span, 0.0f, 1.0f) : 0.0f};
    };
    for (size_t k = 0; k < sections.size(); ++k) {
      const auto [first, last] = sections[k];
      for (int i = first; i < last; ++i) {
        const int joint = chain[i];
        if (joint == pelvis) continue;  // the pelvis frame decides
        const Eigen::Vector3f bone = t.rest_positions[chain[i + 1]] - t.rest_positions[joint];
        JointMap map;
        map.from = source_point(k, i);
        map.to = source_point(k, i + 1);
        const Eigen::Vector3f chord = PointOf(map.to, s.rest_positions) - PointOf(map.from, s.rest_positions);
        // A bone of no length, or one whose source section has none (a clavicle the database rig
        // lacks): keeps its rest rotation.
        if (bone.norm() < 1e-6f || chord.norm() < 1e-6f) continue;
        map.rule = Rule::kChainBone;
        map.owner = map.from.weight < 1.0f ? map.from.a : map.from.b;
        map.source_rest_chord = chord.normalized();
        map.alignment = RestAlignment(bone.normalized(), t, map.source_rest_chord, s);
        maps_[joint] = map;
      }
    }
    const int end = chain.back();
    if (group == kSpine) {
      if (end != pelvis) maps_[end].rule = Rule::kChestFrame;
      continue;
    }
    JointMap map;
    map.rule = Rule::kEndJoint;
    map.owner = source_chain.back();
    map.alignment = RestAlignment(EndDirection(t, group), t, EndDirection(s, group), s);
    maps_[end] = map;
  }
  maps_[pelvis].rule = Rule::kPelvisFrame;
  target_chest_rest_ = ChestFrame(t, t.rest_positions);
  if (!target_chest_rest_.allFinite() || !ChestFrame(s, s.rest_positions).allFinite()) {
    return absl::FailedPreconditionError("the rig's chest has no frame (head or shoulders on top of the chest)");
  }
  return absl::OkStatus();
}

Eigen::Vector3f Retargeter::PointOf(const ChainPoint& point, const std::vector<Eigen::Vector3f>& positions) const {
  return (1.0f - point.weight) * positions[point.a] + point.weight * positions[point.b];
}

void Retargeter::ForwardKinematics(const BodyPose& pose) {
  const Skeleton& skeleton = target_.skeleton;
  world_rotations_[0] = pose.rotations[0];
  world_positions_[0] = pose.root_position;
  for (int j = 1; j < skeleton.num_joints(); ++j) {
    const int p = skeleton.parent(j);
    world_rotations_[j] = (world_rotations_[p] * pose.rotations[j]).normalized();
    world_positions_[j] = world_positions_[p] + world_rotations_[p] * skeleton.joint(j).offset;
  }
}

void Retargeter::ReachWithLimb(BodyGroup limb, const Eigen::Vector3f& goal, const Eigen::Vector3f& fallback_bend,
                               BodyPose* pose) {
  const int g = static_cast<int>(limb);
  const std::vector<int>& chain = target_.chains.joints[g];
  const int a = chain[target_.anchors[g].root], b = chain[target_.anchors[g].middle], c = chain.back();
  const std::vector<Eigen::Quaternionf>& w = world_rotations_;
  const TwoBoneTurns turns =
      SolveTwoBoneIk(world_positions_[a], world_positions_[b], world_positions_[c], goal, fallback_bend);
  // Joints from a to b turn by root_turn, joints below b by root_turn · middle_turn; c keeps its
  // world rotation (the hand or foot still points where the source's does).
  std::vector<Eigen::Quaternionf>& local = pose->rotations;
  local[a] = (local[a] * (w[a].conjugate() * turns.root_turn * w[a])).normalized();
  local[b] = (local[b] * (w[b].conjugate() * turns.middle_turn * w[b])).normalized();
  const Eigen::Quaternionf parent_of_c = turns.root_turn * turns.middle_turn * w[target_.skeleton.parent(c)];
  local[c] = (parent_of_c.conjugate() * w[c]).normalized();
}

void Retargeter::Retarget(const std::vector<Eigen::Quaternionf>& source_rotations,
                          const std::vector<Eigen::Vector3f>& source_positions, BodyPose* out) {
  const Skeleton& skeleton = target_.skeleton;
  const int joints = skeleton.num_joints();
  std::vector<Eigen::Quaternionf>& w = world_rotations_;
  const Eigen::Quaternionf pelvis_rotation(
      Eigen::Matrix3f(PelvisFrame(source_, source_positions) * target_.rest_body_frame.transpose()));
  // 1–3: world rotations, parents first.
  for (int j = 0; j < joints; ++j) {
    const JointMap& map = maps_[j];
    const int parent = skeleton.parent(j);
    switch (map.rule) {
      case Rule::kPelvisFrame:
        w[j] = pelvis_rotation;
        break;
      case Rule::kChestFrame:
        w[j] =
            Eigen::Quaternionf(Eigen::Matrix3f(ChestFrame(source_, source_positions) * target_chest_rest_.transpose()));
        break;
      case Rule::kEndJoint:
        w[j] = source_rotations[map.owner] * map.alignment;
        break;
      case Rule::kChainBone: {
        const Eigen::Quaternionf carried = source_rotations[map.owner] * map.alignment;
        const Eigen::Vector3f chord = PointOf(map.to, source_positions) - PointOf(map.from, source_positions);
        const Eigen::Vector3f predicted = source_rotations[map.owner] * map.source_rest_chord;
        w[j] = chord.norm() > 1e-6f ? Eigen::Quaternionf::FromTwoVectors(predicted, chord) * carried : carried;
        break;
      }
      case Rule::kRest:
        // Joints above the pelvis turn with it (the root is placed from the pelvis below).
        w[j] = parent < 0 || std::find(pelvis_path_.begin(), pelvis_path_.end(), j) != pelvis_path_.end()
                   ? pelvis_rotation
                   : w[parent];
        break;
    }
    w[j].normalize();
  }
  out->rotations.resize(joints);
  for (int j = 0; j < joints; ++j) {
    const int parent = skeleton.parent(j);
    out->rotations[j] = parent < 0 ? w[j] : (w[parent].conjugate() * w[j]).normalized();
  }
  // 4: the pelvis where the source's is, scaled by the leg ratio about the floor under the first
  // frame's pelvis (not the world origin, which would put a larger avatar metres from where the
  // performer is); the root above it.
  const Eigen::Vector3f& source_pelvis = source_positions[source_.topology.landmarks.pelvis];
  if (!anchor_) anchor_ = Eigen::Vector3f(source_pelvis.x(), 0.0f, source_pelvis.z());
  const auto scaled = [this](const Eigen::Vector3f& p) -> Eigen::Vector3f {
    return *anchor_ + scale_ * (p - *anchor_);
  };
  Eigen::Vector3f above_pelvis = Eigen::Vector3f::Zero();
  for (int j : pelvis_path_) above_pelvis += skeleton.joint(j).offset;
  out->root_position = scaled(source_pelvis) - pelvis_rotation * above_pelvis;
  ForwardKinematics(*out);

  const BodyLandmarks& sl = source_.topology.landmarks;
  const Eigen::Vector3f body_left = pelvis_rotation * target_.rest_body_frame.col(0);
  auto bend_of_source = [&](BodyGroup limb) {
    const int g = static_cast<int>(limb);
    const std::vector<int>& chain = source_.chains.joints[g];
    const Eigen::Vector3f a = source_positions[chain[source_.anchors[g].root]];
    const Eigen::Vector3f b = source_positions[chain[source_.anchors[g].middle]];
    const Eigen::Vector3f normal = (a - b).cross(source_positions[chain.back()] - b);
    return normal.norm() > 1e-6f ? normal : Eigen::Vector3f(body_left);
  };
  ReachWithLimb(BodyGroup::kLeftLeg, scaled(source_positions[sl.left_ankle]), bend_of_source(BodyGroup::kLeftLeg), out);
  ReachWithLimb(BodyGroup::kRightLeg, scaled(source_positions[sl.right_ankle]), bend_of_source(BodyGroup::kRightLeg),
                out);
  const BodyGroup arms[2] = {BodyGroup::kLeftArm, BodyGroup::kRightArm};
  const int source_wrists[2] = {sl.left_wrist, sl.right_wrist};
  for (int side = 0; side < 2; ++side) {
    const Eigen::Vector3f source_reach =
        source_positions[source_wrists[side]] - source_positions[LimbRoot(source_, arms[side])];
    const Eigen::Vector3f goal = world_positions_[LimbRoot(target_, arms[side])] +
                                 source_reach * (target_.arm_length[side] / source_.arm_length[side]);
    ReachWithLimb(arms[side], goal, bend_of_source(arms[side]), out);
  }
  ForwardKinematics(*out);
}

}  // namespace mocap

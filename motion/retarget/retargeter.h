// Retargeting of reconstructed frames from the database's rig onto a caller's rig (issue #12),
// frame by frame (so the stream and the offline path share it), in world space:
//  1. Bone directions. Each target chain (spine, head, arms, legs; RetargetRig) is cut at the
//     anchors both bodies have (shoulder/hip, elbow/knee, wrist/ankle); a target joint at a
//     fraction of its section's rest length takes the source point at the same fraction of the
//     source section, so any joint count per section works (split bones, twist joints on the
//     path, no clavicle). A target bone points where the source's chord between its two points
//     points; its twist comes from the source joint that carries the chord, through a rest
//     alignment: the rotation taking the target's rest bone to the source's rest bone with the
//     rest body's forward (up, for bones along forward) kept on the same side. Rest poses can
//     differ (T-pose, A-pose, every bone along one axis): only rest bone frames are compared,
//     rotations are never copied joint to joint, so nothing flips.
//  2. The pelvis and the chest take the body frame the source's hips and shoulders span
//     (up along the spine, left from right hip/shoulder to left); wrists, ankles and the head take
//     their source joint's rotation through the same rest alignment (hands, feet and head point
//     where the source's do).
//  3. Joints without a counterpart keep their rest rotation relative to their parent, so they
//     follow their chain: fingers and toes move with the hand and foot, twist and "share" leaves
//     with their bone, face joints with the head; joints above the pelvis stay at rest and the
//     root is placed so the pelvis lands where step 4 says.
//  4. Positions: the pelvis and the ankles go where the source's are, scaled by the leg-length
//     ratio k = target leg / source leg about the world origin (the floor at y = 0 stays the
//     floor; a planted source foot is a planted target foot: no new skating); each hand goes to
//     the target shoulder plus the source's shoulder-to-wrist vector scaled by the arms' length
//     ratio. Two-bone IK on each target limb (hip-knee-ankle, shoulder-elbow-wrist) reaches
//     those points; hands and feet keep the world orientation of step 2.
//
// Thread safety: one Retargeter per session (it keeps per-frame scratch space); Retarget does
// not allocate once warmed up.
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "absl/status/statusor.h"
#include "motion/reconstruct/body_model.h"
#include "motion/retarget/retarget_rig.h"

namespace mocap {

class Retargeter {
 public:
  // `source`: the database's rig (SourceRigOf), `target`: the caller's. Both are kept.
  static absl::StatusOr<Retargeter> Create(RetargetRig source, RetargetRig target);

  const RetargetRig& source() const { return source_; }
  const RetargetRig& target() const { return target_; }
  // k: target leg length / source leg length. Positions scale about the floor under the first
  // retargeted frame's pelvis (anchor()), so the avatar starts where the performer stands.
  float scale() const { return scale_; }
  const std::optional<Eigen::Vector3f>& anchor() const { return anchor_; }

  // One frame. `source_rotations` and `source_positions`: world transforms of every source joint
  // (metres, Y up; BodyModel::WorldTransforms). `out`: the target's root position (metres, Y up)
  // and every joint's local rotation, target joint order.
  void Retarget(const std::vector<Eigen::Quaternionf>& source_rotations,
                const std::vector<Eigen::Vector3f>& source_positions, BodyPose* out);
  // The same for a pose of the database's body (BodyModel of the source rig).
  void Retarget(const BodyModel& source_body, const BodyPose& source_pose, BodyPose* out) {
    source_body.WorldTransforms(source_pose, &source_rotations_, &source_positions_);
    Retarget(source_rotations_, source_positions_, out);
  }
  // World transforms of the last Retarget's result (metres, Y up), target joint order.
  const std::vector<Eigen::Quaternionf>& world_rotations() const { return world_rotations_; }
  const std::vector<Eigen::Vector3f>& world_positions() const { return world_positions_; }

 private:
  enum class Rule : unsigned char { kRest, kPelvisFrame, kChestFrame, kChainBone, kEndJoint };
  // A point of a source chain: (1 − weight)·joint a + weight·joint b.
  struct ChainPoint {
    int a = 0, b = 0;
    float weight = 0.0f;
  };
  struct JointMap {
    Rule rule = Rule::kRest;
    int owner = -1;                                                 // source joint whose rotation carries the twist
    Eigen::Quaternionf alignment = Eigen::Quaternionf::Identity();  // target rest -> source rest
    ChainPoint from, to;                                            // kChainBone: the source chord
    Eigen::Vector3f source_rest_chord = Eigen::Vector3f::Zero();    // unit, source rest
  };
  Retargeter() = default;
  absl::Status MapJoints();
  Eigen::Vector3f PointOf(const ChainPoint& point, const std::vector<Eigen::Vector3f>& positions) const;
  void ForwardKinematics(const BodyPose& pose);
  void ReachWithLimb(BodyGroup limb, const Eigen::Vector3f& target, const Eigen::Vector3f& fallback_bend,
                     BodyPose* pose);

  RetargetRig source_, target_;
  float scale_ = 1.0f;
  std::optional<Eigen::Vector3f> anchor_;  // set by the first Retarget
  std::vector<JointMap> maps_;
  std::vector<int> pelvis_path_;                                     // target joints from below the root to the pelvis
  Eigen::Matrix3f target_chest_rest_ = Eigen::Matrix3f::Identity();  // the chest's rest frame
  std::vector<Eigen::Quaternionf> source_rotations_, world_rotations_;
  std::vector<Eigen::Vector3f> source_positions_;
  std::vector<Eigen::Vector3f> world_positions_;
};

// Two directions -> rotation whose columns are (left, up, left × up); `up` wins when they are
// not orthogonal. Used for body frames (pelvis, chest) and rest bone frames.
Eigen::Matrix3f FrameFromUpLeft(const Eigen::Vector3f& up, const Eigen::Vector3f& left);

}  // namespace mocap

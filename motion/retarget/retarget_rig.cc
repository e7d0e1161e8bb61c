#include "motion/retarget/retarget_rig.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "motion/bvh/bvh_reader.h"
#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"
#include "motion/skeleton/forward_kinematics.h"
#include "motion/skeleton/limb_segments.h"

namespace mocap {
namespace {

constexpr BodyGroup kLimbs[4] = {BodyGroup::kLeftArm, BodyGroup::kRightArm, BodyGroup::kLeftLeg, BodyGroup::kRightLeg};

int IndexIn(const std::vector<int>& chain, int joint) {
  const auto it = std::find(chain.begin(), chain.end(), joint);
  return it == chain.end() ? -1 : static_cast<int>(it - chain.begin());
}

// Rest length along `chain` from index `from` to index `to` (from <= to).
float LengthAlong(const RetargetRig& rig, const std::vector<int>& chain, int from, int to) {
  float length = 0.0f;
  for (int i = from; i < to; ++i) length += (rig.rest_positions[chain[i + 1]] - rig.rest_positions[chain[i]]).norm();
  return length;
}

// The shoulder (hip) on a limb chain from its rest lengths (motion/skeleton/limb_segments.h).
int RestUpperSegmentStart(const RetargetRig& rig, const std::vector<int>& chain, int middle) {
  std::vector<float> cumulative(chain.size(), 0.0f);
  for (int i = 1; i < static_cast<int>(chain.size()); ++i)
    cumulative[i] = cumulative[i - 1] + LengthAlong(rig, chain, i - 1, i);
  return UpperSegmentStart(cumulative, middle);
}

Skeleton ScaledSkeleton(const Skeleton& skeleton, float factor) {
  std::vector<Joint> joints = skeleton.joints();
  for (Joint& joint : joints) {
    joint.offset *= factor;
    if (joint.end_site) *joint.end_site *= factor;
  }
  return Skeleton(std::move(joints));
}

absl::StatusOr<RetargetRig> RigFromClip(BvhClip clip, std::optional<LengthUnit> unit) {
  MOCAP_RETURN_IF_ERROR(clip.skeleton.Validate());
  if (clip.num_frames() > kMaxTargetFrames) clip.channels.conservativeResize(kMaxTargetFrames, Eigen::NoChange);
  // Without frames the analysis reads the zero-rotation pose itself.
  if (clip.num_frames() == 0) clip.channels = ChannelMatrix::Zero(1, clip.skeleton.num_channels());
  const LocalMotion motion =
      MotionFromChannels(clip.skeleton, clip.channels, clip.frame_time > 0 ? clip.frame_time : 1.0 / 30);
  absl::StatusOr<BodyTopology> topology = AnalyseBody(clip.skeleton, motion, BodyTopologyOptions{.unit = unit});
  if (!topology.ok()) {
    return absl::FailedPreconditionError(
        StrCat("the target rig is not a recognisable humanoid: ", topology.status().message()));
  }
  const float metres = static_cast<float>(MetresPerUnit(topology->unit));
  MOCAP_ASSIGN_OR_RETURN(RetargetRig rig, MakeRetargetRig(ScaledSkeleton(clip.skeleton, metres), *topology));
  rig.unit = topology->unit;
  rig.to_y_up = Eigen::Quaternionf::FromTwoVectors(topology->up(), Eigen::Vector3f::UnitY());
  return rig;
}

}  // namespace

absl::StatusOr<RetargetRig> MakeRetargetRig(const Skeleton& skeleton_in_metres, const BodyTopology& topology) {
  RetargetRig rig;
  rig.skeleton = skeleton_in_metres;
  rig.topology = topology;
  rig.chains = MakeBodyChains(rig.skeleton, topology);
  const GlobalPoses rest = ForwardKinematics(rig.skeleton, RestMotion(rig.skeleton));
  rig.rest_positions.resize(rig.skeleton.num_joints());
  for (int j = 0; j < rig.skeleton.num_joints(); ++j) rig.rest_positions[j] = rest.position(0, j);

  const BodyLandmarks& l = topology.landmarks;
  const int middles[4] = {l.left_elbow, l.right_elbow, l.left_knee, l.right_knee};
  for (int limb = 0; limb < 4; ++limb) {
    const int group = static_cast<int>(kLimbs[limb]);
    const std::vector<int>& chain = rig.chains.joints[group];
    const int middle = IndexIn(chain, middles[limb]);
    if (middle <= 0 || middle + 1 >= static_cast<int>(chain.size())) {
      return absl::FailedPreconditionError(
          StrCat("the ", BodyGroupName(kLimbs[limb]), " has no elbow or knee between its top and its end"));
    }
    rig.anchors[group] = {RestUpperSegmentStart(rig, chain, middle), middle};
  }
  auto limb_length = [&](BodyGroup group) {
    const std::vector<int>& chain = rig.chains.joints[static_cast<int>(group)];
    return LengthAlong(rig, chain, rig.anchors[static_cast<int>(group)].root, static_cast<int>(chain.size()) - 1);
  };
  rig.leg_length = 0.5f * (limb_length(BodyGroup::kLeftLeg) + limb_length(BodyGroup::kRightLeg));
  rig.arm_length = {limb_length(BodyGroup::kLeftArm), limb_length(BodyGroup::kRightArm)};
  if (!(rig.leg_length > 1e-3f) || !(rig.arm_length[0] > 1e-3f) || !(rig.arm_length[1] > 1e-3f)) {
    return absl::FailedPreconditionError("the rig's legs or arms have no length");
  }

  // Body frame of the rest pose: up along the spine, left from the right hip to the left one.
  const std::vector<int>& spine = rig.chains.joints[static_cast<int>(BodyGroup::kSpine)];
  Eigen::Vector3f up = rig.rest_positions[spine.back()] - rig.rest_positions[l.pelvis];
  if (up.norm() < 0.05f * rig.leg_length) up = rig.rest_positions[l.head] - rig.rest_positions[l.pelvis];
  auto hip = [&](BodyGroup leg) {
    const int group = static_cast<int>(leg);
    return rig.rest_positions[rig.chains.joints[group][rig.anchors[group].root]];
  };
  Eigen::Vector3f left = hip(BodyGroup::kLeftLeg) - hip(BodyGroup::kRightLeg);
  if (up.norm() < 1e-4f || left.norm() < 1e-4f) {
    return absl::FailedPreconditionError("the rig's rest pose has no body frame (spine or hips of zero length)");
  }
  up.normalize();
  left -= up * up.dot(left);
  if (left.norm() < 1e-4f) return absl::FailedPreconditionError("the rig's rest pose has its hips along its spine");
  left.normalize();
  rig.rest_body_frame.col(0) = left;
  rig.rest_body_frame.col(1) = up;
  rig.rest_body_frame.col(2) = left.cross(up);
  return rig;
}

absl::StatusOr<RetargetRig> SourceRigOf(const RigModel& rig, const Skeleton& body_skeleton) {
  BodyTopology topology = rig.topology;
  BodyLandmarks& l = topology.landmarks;
  if (l.left_elbow < 0 || l.right_elbow < 0 || l.left_knee < 0 || l.right_knee < 0) {
    // A rig stored before elbows and knees were kept: the same analysis on its reference pose.
    LocalMotion reference;
    reference.Resize(1, body_skeleton.num_joints());
    for (int j = 0; j < body_skeleton.num_joints(); ++j) {
      reference.SetRotation(0, j, rig.reference_rotations[j]);
      reference.SetTranslation(0, j, body_skeleton.joint(j).offset);
    }
    MOCAP_ASSIGN_OR_RETURN(const BodyTopology again,
                           AnalyseBody(body_skeleton, reference, BodyTopologyOptions{.unit = LengthUnit::kMetre}));
    const BodyLandmarks& a = again.landmarks;
    if (a.left_wrist != l.left_wrist || a.right_wrist != l.right_wrist || a.left_ankle != l.left_ankle ||
        a.right_ankle != l.right_ankle) {
      return absl::FailedPreconditionError(
          "the database's rig needs re-importing for retargeting (elbows and knees "
          "were not stored with it)");
    }
    l.left_elbow = a.left_elbow;
    l.right_elbow = a.right_elbow;
    l.left_knee = a.left_knee;
    l.right_knee = a.right_knee;
  }
  MOCAP_ASSIGN_OR_RETURN(RetargetRig source, MakeRetargetRig(body_skeleton, topology));
  source.unit = rig.unit;
  source.to_y_up = rig.to_y_up;
  return source;
}

absl::StatusOr<RetargetRig> TargetRigFromBvh(std::string_view text, std::optional<LengthUnit> unit) {
  // A hierarchy alone is a rig too: give it one frame of its zero-rotation pose for the reader.
  std::string with_motion;
  if (text.find("MOTION") == std::string_view::npos) {
    int channels = 0;
    for (size_t at = text.find("CHANNELS"); at != std::string_view::npos; at = text.find("CHANNELS", at + 8)) {
      // A count outside 0..6 is refused by the reader at its line: never sized from here (a
      // 90-byte "CHANNELS 99999999" asked for gigabytes of zeros; issue #24 finding 4).
      channels += std::clamp(std::atoi(std::string(text.substr(at + 8, 8)).c_str()), 0, 6);
    }
    with_motion = StrCat(text, "\nMOTION\nFrames: 1\nFrame Time: 0.0333333\n");
    for (int c = 0; c < channels; ++c) with_motion += c ? " 0" : "0";
    with_motion += "\n";
    text = with_motion;
  }
  MOCAP_ASSIGN_OR_RETURN(BvhClip clip, ParseBvh(text, "target rig"));
  if (clip.skeleton.num_joints() > kMaxTargetJoints) {
    return absl::InvalidArgumentError(
        StrCat("the target rig has ", clip.skeleton.num_joints(), " joints (at most ", kMaxTargetJoints, ")"));
  }
  return RigFromClip(std::move(clip), unit);
}

absl::StatusOr<RetargetRig> TargetRigFromClip(const BvhClip& clip, std::optional<LengthUnit> unit) {
  return RigFromClip(clip, unit);
}

absl::StatusOr<RetargetRig> TargetRigFromSkeleton(const Skeleton& skeleton, std::optional<LengthUnit> unit) {
  BvhClip clip;
  clip.skeleton = skeleton;
  clip.frame_time = 1.0 / 30;
  return RigFromClip(std::move(clip), unit);
}

}  // namespace mocap

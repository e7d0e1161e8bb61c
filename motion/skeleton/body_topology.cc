#include "motion/skeleton/body_topology.h"

#include <algorithm>
#include <array>
#include <vector>

#include "motion/core/str_cat.h"
#include "motion/skeleton/body_topology_steps.h"
#include "motion/skeleton/forward_kinematics.h"

namespace mocap {
namespace {

namespace steps = body_topology;

// Orders a pair's items left first.
template <typename T>
std::array<T, 2> LeftFirst(const std::array<T, 2>& pair, bool first_is_left) {
  return first_is_left ? pair : std::array<T, 2>{pair[1], pair[0]};
}

// Wrists, ankles, elbows, knees, shoulders and hips from the limb joints of each side (left first).
void SetLimbLandmarks(const std::array<steps::LimbJoints, 2>& arms, const std::array<steps::LimbJoints, 2>& legs,
                      BodyLandmarks* landmarks) {
  landmarks->left_wrist = arms[0].end;
  landmarks->right_wrist = arms[1].end;
  landmarks->left_ankle = legs[0].end;
  landmarks->right_ankle = legs[1].end;
  landmarks->left_elbow = arms[0].middle;
  landmarks->right_elbow = arms[1].middle;
  landmarks->left_knee = legs[0].middle;
  landmarks->right_knee = legs[1].middle;
  landmarks->left_shoulder = arms[0].start;
  landmarks->right_shoulder = arms[1].start;
  landmarks->left_hip = legs[0].start;
  landmarks->right_hip = legs[1].start;
}

}  // namespace

std::string_view BodyGroupName(BodyGroup group) {
  switch (group) {
    case BodyGroup::kSpine:
      return "spine";
    case BodyGroup::kHead:
      return "head";
    case BodyGroup::kLeftArm:
      return "left_arm";
    case BodyGroup::kRightArm:
      return "right_arm";
    case BodyGroup::kLeftLeg:
      return "left_leg";
    case BodyGroup::kRightLeg:
      return "right_leg";
  }
  return "?";
}

int BodyTopology::group_size(BodyGroup group) const {
  return static_cast<int>(std::count(group_of_joint.begin(), group_of_joint.end(), group));
}

absl::StatusOr<BodyTopology> AnalyseBody(const Skeleton& skeleton, const LocalMotion& motion,
                                         const BodyTopologyOptions& options) {
  if (motion.num_joints() != skeleton.num_joints() || motion.num_frames() < 1) {
    return absl::InvalidArgumentError("motion does not match the skeleton");
  }
  const GlobalPoses poses = ForwardKinematics(skeleton, motion);
  const std::vector<int> frames = steps::SampleFrames(motion.num_frames());

  // 1. The tree of real bones.
  const Eigen::VectorXf bone = steps::StaticBoneLengths(motion);
  const steps::TreeMetric metric(skeleton, bone);
  const float body_size = steps::BodySize(metric);
  if (body_size <= 0.0f) return absl::FailedPreconditionError("skeleton has no bones of non-zero length");
  const steps::MergedTree tree = steps::MergeShortBones(skeleton, bone, body_size);
  const std::vector<bool> overlay = steps::FindOverlayChains(skeleton, tree, poses, frames);
  const std::vector<int> candidates = steps::LimbEndCandidates(tree, overlay);
  if (candidates.size() < 5) {
    return absl::FailedPreconditionError(
        StrCat("not a humanoid rig: found ", candidates.size(), " limb ends; two arms, two legs and a head need five"));
  }

  // 2. The five limb ends (and no sixth); 3. head, limb pairs and pelvis.
  const std::array<int, 5> ends = steps::PickLimbEnds(candidates, metric);
  if (const std::optional<int> extra = steps::ExtraLimb(candidates, ends, metric)) {
    return absl::FailedPreconditionError(StrCat("not a humanoid rig: the branch ending at '",
                                                skeleton.joint(*extra).name,
                                                "' is as long as an arm or a leg (more than two arms and two legs: a "
                                                "creature's rig, or a long prop bone?)"));
  }
  const steps::HeadAndPairs body = steps::FindHeadAndPairs(ends, metric);
  BodyTopology topology;
  topology.landmarks.pelvis = body.pelvis;

  // 4. Up, in the clip and in the rest pose.
  const steps::UpAxis up_axis = steps::MeasureUp(poses, frames, body.pelvis, body.head.end);
  const steps::UpAxis rest_up_axis = steps::RestUp(skeleton, body.pelvis, body.head.end);
  topology.up_axis = up_axis.axis;
  topology.up_sign = up_axis.sign;
  topology.up_alignment = up_axis.alignment;
  topology.rest_up_axis = rest_up_axis.axis;
  topology.rest_up_sign = rest_up_axis.sign;
  const Eigen::Vector3f up = topology.up();

  // 5. Arms and legs; 6. where each bends and ends (the first failure in the order leg, leg, arm, arm).
  const steps::ArmsAndLegs limbs = steps::SplitArmsAndLegs(body, metric, poses, frames, up);
  std::array<steps::LimbJoints, 2> arm_joints, leg_joints;
  for (int i = 0; i < 2; ++i) {
    // Each limb beside its mirror: a joint that bends on either side ends a segment on both.
    absl::StatusOr<steps::LimbJoints> leg =
        steps::FindLimbJoints(skeleton, metric, bone, limbs.legs[i], poses, frames, &limbs.legs[1 - i]);
    if (!leg.ok()) return leg.status();
    leg_joints[i] = *leg;
  }
  // The upper arm starts at a shoulder, and the shoulders lie wider apart than the hips: a longer
  // clavicle from the middle of the chest is not the upper arm (docs/method.md B1, step 6 above).
  const float hip_separation = steps::MeanDistance(poses, frames, leg_joints[0].start, leg_joints[1].start);
  for (int i = 0; i < 2; ++i) {
    absl::StatusOr<steps::LimbJoints> arm =
        steps::FindLimbJoints(skeleton, metric, bone, limbs.arms[i], poses, frames, &limbs.arms[1 - i], hip_separation);
    if (!arm.ok()) return arm.status();
    arm_joints[i] = *arm;
  }

  // 7. Facing and sides, frame by frame: each frame's hip line and its knee and toe cues side the
  // legs, the arms are sided against the same per-frame body (no clip mean: a walk in a circle has
  // no mean facing).
  const absl::StatusOr<steps::Sides> sides =
      steps::FindSides(limbs, arm_joints, leg_joints, body.pelvis, metric, poses, frames, up, body_size);
  if (!sides.ok()) return sides.status();
  topology.forward = sides->forward;
  const bool arm0_left = sides->first_arm_is_left;
  const bool leg0_left = sides->first_leg_is_left;
  const std::array<steps::Limb, 2> arms = LeftFirst(limbs.arms, arm0_left);
  const std::array<steps::Limb, 2> legs = LeftFirst(limbs.legs, leg0_left);

  // 8. Landmarks, groups, sizes and unit.
  SetLimbLandmarks(LeftFirst(arm_joints, arm0_left), LeftFirst(leg_joints, leg0_left), &topology.landmarks);
  topology.landmarks.head = steps::HeadLandmark(body.head, metric, tree);
  steps::AssignGroups(
      skeleton,
      steps::SidedLimbs{
          .head = body.head, .left_arm = arms[0], .right_arm = arms[1], .left_leg = legs[0], .right_leg = legs[1]},
      body.pelvis, &topology);
  topology.leg_length = steps::LegLength(limbs.legs, leg_joints, metric, bone);
  const steps::Heights heights = steps::MeasureHeights(topology.group_of_joint, body.pelvis, poses, up);
  topology.standing_pelvis_height = heights.standing_pelvis;
  topology.floor_height = heights.floor;
  topology.unit_detected = !options.unit.has_value();
  topology.unit = options.unit ? *options.unit : DetectUnitFromLegLength(topology.leg_length);
  return topology;
}

}  // namespace mocap

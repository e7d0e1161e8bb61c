#include "motion/skeleton/body_topology.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <ostream>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "motion/bvh/bvh_reader.h"
#include "motion/core/units.h"
#include "motion/skeleton/forward_kinematics.h"
#include "motion/skeleton/local_motion.h"
#include "tests/support/shared_data.h"
#include "tests/support/synthetic_clip.h"

namespace mocap {
namespace {

using testing::MakeWalkingClip;
using testing::SyntheticRigOptions;

SyntheticRigOptions RigFromBits(int bits, const std::string& order = "ZXY") {
  return testing::SyntheticRigFromBits(bits, order);
}

std::string Describe(const SyntheticRigOptions& o) {
  std::string s;
  if (o.extra_root) s += "extra_root ";
  if (o.z_up) s += "z_up ";
  if (o.fingers_and_toes) s += "fingers_and_toes ";
  if (o.twist_bones) s += "twist_bones ";
  if (o.position_channels_everywhere) s += "position_channels_everywhere ";
  return s + o.rotation_order + " scale " + std::to_string(o.length_scale);
}

int Find(const Skeleton& skeleton, const std::string& name) {
  const int index = skeleton.Find(name);
  EXPECT_GE(index, 0) << "no joint " << name;
  return index;
}

std::string NameOf(const Skeleton& skeleton, int index) {
  return index >= 0 && index < skeleton.num_joints() ? skeleton.joint(index).name : "<" + std::to_string(index) + ">";
}

// The group each synthetic joint belongs to, from its name (the answer key).
BodyGroup ExpectedGroup(const std::string& name) {
  auto starts = [&](const char* prefix) { return name.rfind(prefix, 0) == 0; };
  auto has = [&](const char* part) { return name.find(part) != std::string::npos; };
  const bool leg_part = has("UpLeg") || has("Leg") || has("Foot") || has("Toe") || has("Knee");
  if (starts("Left")) return leg_part ? BodyGroup::kLeftLeg : BodyGroup::kLeftArm;
  if (starts("Right")) return leg_part ? BodyGroup::kRightLeg : BodyGroup::kRightArm;
  if (name == "Neck" || name == "Head") return BodyGroup::kHead;
  return BodyGroup::kSpine;  // RL_BoneRoot, Root, Hips, Pelvis, Spine, Chest
}

absl::StatusOr<BodyTopology> Analyse(const BvhClip& clip, const BodyTopologyOptions& options = {}) {
  return AnalyseBody(clip.skeleton, MotionFromChannels(clip.skeleton, clip.channels, clip.frame_time), options);
}

// Expects the landmarks to be the named joints of the synthetic rig.
void ExpectSyntheticLandmarks(const Skeleton& skeleton, const BodyLandmarks& landmarks) {
  EXPECT_EQ(NameOf(skeleton, landmarks.left_wrist), "LeftHand");
  EXPECT_EQ(NameOf(skeleton, landmarks.right_wrist), "RightHand");
  EXPECT_EQ(NameOf(skeleton, landmarks.left_ankle), "LeftFoot");
  EXPECT_EQ(NameOf(skeleton, landmarks.right_ankle), "RightFoot");
  EXPECT_EQ(NameOf(skeleton, landmarks.pelvis), "Hips");
  EXPECT_EQ(NameOf(skeleton, landmarks.head), "Head");
}

// ---------------------------------------------------------------------------------------------
// Every rig option combination and several Euler orders.

class BodyTopologyRigTest : public ::testing::TestWithParam<std::tuple<int, std::string>> {};

TEST_P(BodyTopologyRigTest, FindsLandmarksGroupsUpAndUnit) {
  const SyntheticRigOptions options = RigFromBits(std::get<0>(GetParam()), std::get<1>(GetParam()));
  SCOPED_TRACE(Describe(options));
  const BvhClip clip = MakeWalkingClip(options, 40);
  const Skeleton& skeleton = clip.skeleton;
  const absl::StatusOr<BodyTopology> result = Analyse(clip);
  ASSERT_TRUE(result.ok()) << result.status();
  const BodyTopology& topology = *result;

  ExpectSyntheticLandmarks(skeleton, topology.landmarks);
  EXPECT_EQ(topology.up_axis, 1);
  EXPECT_EQ(topology.up_sign, 1);
  EXPECT_GT(topology.up_alignment, 0.95f);
  EXPECT_TRUE(topology.up().isApprox(Eigen::Vector3f::UnitY()));
  EXPECT_EQ(topology.rest_up_axis, options.z_up ? 2 : 1);
  EXPECT_EQ(topology.rest_up_sign, 1);
  // The character faces +Z.
  EXPECT_GT(topology.forward.z(), 0.95f) << topology.forward.transpose();
  EXPECT_NEAR(topology.forward.norm(), 1.0f, 1e-4f);
  EXPECT_NEAR(topology.forward.y(), 0.0f, 1e-4f);

  EXPECT_EQ(topology.unit, LengthUnit::kCentimetre);
  EXPECT_TRUE(topology.unit_detected);
  EXPECT_NEAR(topology.leg_length, testing::kSyntheticLegLength, 0.5);
  // Hips ~92 cm above the floor on average; the lowest leg joint is a toe at 0.5 cm in stance.
  EXPECT_GT(topology.standing_pelvis_height, 85.0f);
  EXPECT_LT(topology.standing_pelvis_height, 96.0f);
  EXPECT_NEAR(topology.floor_height, testing::kSyntheticToeHeight, 0.5);

  // Group of every joint.
  ASSERT_EQ(static_cast<int>(topology.group_of_joint.size()), skeleton.num_joints());
  for (int j = 0; j < skeleton.num_joints(); ++j) {
    EXPECT_EQ(BodyGroupName(topology.group_of_joint[j]), BodyGroupName(ExpectedGroup(skeleton.joint(j).name)))
        << skeleton.joint(j).name;
  }
  EXPECT_EQ(NameOf(skeleton, topology.group_top[static_cast<int>(BodyGroup::kLeftLeg)]), "LeftUpLeg");
  EXPECT_EQ(NameOf(skeleton, topology.group_top[static_cast<int>(BodyGroup::kRightLeg)]), "RightUpLeg");
  EXPECT_EQ(NameOf(skeleton, topology.group_top[static_cast<int>(BodyGroup::kLeftArm)]), "LeftShoulder");
  EXPECT_EQ(NameOf(skeleton, topology.group_top[static_cast<int>(BodyGroup::kRightArm)]), "RightShoulder");
  EXPECT_EQ(NameOf(skeleton, topology.group_top[static_cast<int>(BodyGroup::kHead)]), "Neck");
  EXPECT_EQ(NameOf(skeleton, topology.group_end[static_cast<int>(BodyGroup::kHead)]), "Head");
  // Each limb group's end lies in that group.
  for (BodyGroup g :
       {BodyGroup::kHead, BodyGroup::kLeftArm, BodyGroup::kRightArm, BodyGroup::kLeftLeg, BodyGroup::kRightLeg}) {
    const int end = topology.group_end[static_cast<int>(g)];
    ASSERT_GE(end, 0);
    ASSERT_LT(end, skeleton.num_joints());
    EXPECT_EQ(topology.group_of_joint[end], g) << BodyGroupName(g);
  }
  const int arm_size = 4 + (options.fingers_and_toes ? 15 : 0) + (options.twist_bones ? 5 : 0);
  const int leg_size = 4 + (options.fingers_and_toes ? 5 : 0) + (options.twist_bones ? 5 : 0);
  EXPECT_EQ(topology.group_size(BodyGroup::kLeftArm), arm_size);
  EXPECT_EQ(topology.group_size(BodyGroup::kRightArm), arm_size);
  EXPECT_EQ(topology.group_size(BodyGroup::kLeftLeg), leg_size);
  EXPECT_EQ(topology.group_size(BodyGroup::kRightLeg), leg_size);
  EXPECT_EQ(topology.group_size(BodyGroup::kHead), 2);
}

INSTANTIATE_TEST_SUITE_P(AllRigOptions, BodyTopologyRigTest,
                         ::testing::Combine(::testing::Range(0, 32), ::testing::Values("ZXY", "XYZ", "YZX")),
                         [](const auto& info) {
                           return "Rig" + std::to_string(std::get<0>(info.param)) + "_" + std::get<1>(info.param);
                         });

TEST(BodyTopologyTest, GroupsOfTheRichestRigByName) {
  SyntheticRigOptions options = RigFromBits(31);
  const BvhClip clip = MakeWalkingClip(options, 30);
  const absl::StatusOr<BodyTopology> topology = Analyse(clip);
  ASSERT_TRUE(topology.ok()) << topology.status();
  auto group = [&](const char* name) {
    return std::string(BodyGroupName(topology->group_of_joint[Find(clip.skeleton, name)]));
  };
  EXPECT_EQ(group("LeftToe1"), "left_leg");
  EXPECT_EQ(group("LeftToe5"), "left_leg");
  EXPECT_EQ(group("LeftLegTwist"), "left_leg");
  EXPECT_EQ(group("LeftLegTwistMid"), "left_leg");
  EXPECT_EQ(group("LeftKneeShareBone"), "left_leg");
  EXPECT_EQ(group("RightUpLegTwistMid"), "right_leg");
  EXPECT_EQ(group("LeftHandThumb3"), "left_arm");
  EXPECT_EQ(group("RightHandPinky1"), "right_arm");
  EXPECT_EQ(group("RightElbowShareBone"), "right_arm");
  EXPECT_EQ(group("Neck"), "head");
  EXPECT_EQ(group("Head"), "head");
  EXPECT_EQ(group("Spine"), "spine");
  EXPECT_EQ(group("Chest"), "spine");
  EXPECT_EQ(group("Pelvis"), "spine");
  EXPECT_EQ(group("Hips"), "spine");
  EXPECT_EQ(group("Root"), "spine");
  EXPECT_EQ(group("RL_BoneRoot"), "spine");
}

TEST(BodyTopologyTest, BodyGroupNames) {
  EXPECT_EQ(BodyGroupName(BodyGroup::kSpine), "spine");
  EXPECT_EQ(BodyGroupName(BodyGroup::kHead), "head");
  EXPECT_EQ(BodyGroupName(BodyGroup::kLeftArm), "left_arm");
  EXPECT_EQ(BodyGroupName(BodyGroup::kRightArm), "right_arm");
  EXPECT_EQ(BodyGroupName(BodyGroup::kLeftLeg), "left_leg");
  EXPECT_EQ(BodyGroupName(BodyGroup::kRightLeg), "right_leg");
}

// ---------------------------------------------------------------------------------------------
// Units from body size.

struct ScaleCase {
  double scale;
  LengthUnit unit;
};

class BodyTopologyUnitTest : public ::testing::TestWithParam<std::tuple<ScaleCase, int>> {};

TEST_P(BodyTopologyUnitTest, DetectsUnitFromLegLength) {
  const auto [scale_case, bits] = GetParam();
  SyntheticRigOptions options = RigFromBits(bits);
  options.length_scale = scale_case.scale;
  SCOPED_TRACE(Describe(options));
  const BvhClip clip = MakeWalkingClip(options, 30);
  const absl::StatusOr<BodyTopology> topology = Analyse(clip);
  ASSERT_TRUE(topology.ok()) << topology.status();
  ExpectSyntheticLandmarks(clip.skeleton, topology->landmarks);
  EXPECT_EQ(UnitName(topology->unit), UnitName(scale_case.unit));
  EXPECT_TRUE(topology->unit_detected);
  EXPECT_NEAR(topology->leg_length, testing::kSyntheticLegLength * scale_case.scale,
              0.005 * testing::kSyntheticLegLength * scale_case.scale);
  const double pelvis_metres = topology->standing_pelvis_height * MetresPerUnit(topology->unit);
  EXPECT_GT(pelvis_metres, 0.85);
  EXPECT_LT(pelvis_metres, 0.96);
}

INSTANTIATE_TEST_SUITE_P(Scales, BodyTopologyUnitTest,
                         ::testing::Combine(::testing::Values(ScaleCase{1.0, LengthUnit::kCentimetre},
                                                              ScaleCase{0.01, LengthUnit::kMetre},
                                                              ScaleCase{1.0 / 2.54, LengthUnit::kInch},
                                                              ScaleCase{10.0, LengthUnit::kMillimetre}),
                                            ::testing::Values(0, 1 | 4, 2 | 8 | 16)));

TEST(BodyTopologyTest, UnitOverrideIsHonoured) {
  const BvhClip clip = MakeWalkingClip({}, 30);
  const absl::StatusOr<BodyTopology> topology = Analyse(clip, BodyTopologyOptions{.unit = LengthUnit::kInch});
  ASSERT_TRUE(topology.ok()) << topology.status();
  EXPECT_EQ(topology->unit, LengthUnit::kInch);
  EXPECT_FALSE(topology->unit_detected);
  // The sizes stay in file units.
  EXPECT_NEAR(topology->leg_length, testing::kSyntheticLegLength, 0.5);

  SyntheticRigOptions metres;
  metres.length_scale = 0.01;
  const absl::StatusOr<BodyTopology> overridden =
      Analyse(MakeWalkingClip(metres, 30), BodyTopologyOptions{.unit = LengthUnit::kCentimetre});
  ASSERT_TRUE(overridden.ok()) << overridden.status();
  EXPECT_EQ(overridden->unit, LengthUnit::kCentimetre);
  EXPECT_FALSE(overridden->unit_detected);
}

// ---------------------------------------------------------------------------------------------
// Invariances: names, ground-plane placement, mirror image.

Skeleton Renamed(const Skeleton& skeleton) {
  std::vector<Joint> joints = skeleton.joints();
  // Meaningless names in a shuffled-looking but deterministic order.
  for (size_t j = 0; j < joints.size(); ++j) joints[j].name = "j" + std::to_string((j * 7919) % 104729);
  return Skeleton(std::move(joints));
}

TEST(BodyTopologyTest, IgnoresJointNames) {
  for (int bits : {0, 1, 4 | 8, 31}) {
    const SyntheticRigOptions options = RigFromBits(bits);
    SCOPED_TRACE(Describe(options));
    const BvhClip clip = MakeWalkingClip(options, 30);
    const Skeleton renamed = Renamed(clip.skeleton);
    ASSERT_TRUE(renamed.Validate().ok());
    const LocalMotion motion = MotionFromChannels(clip.skeleton, clip.channels, clip.frame_time);
    const absl::StatusOr<BodyTopology> a = AnalyseBody(clip.skeleton, motion);
    const absl::StatusOr<BodyTopology> b = AnalyseBody(renamed, motion);
    ASSERT_TRUE(a.ok()) << a.status();
    ASSERT_TRUE(b.ok()) << b.status();
    ExpectSyntheticLandmarks(clip.skeleton, a->landmarks);
    EXPECT_EQ(b->landmarks.left_wrist, a->landmarks.left_wrist);
    EXPECT_EQ(b->landmarks.right_wrist, a->landmarks.right_wrist);
    EXPECT_EQ(b->landmarks.left_ankle, a->landmarks.left_ankle);
    EXPECT_EQ(b->landmarks.right_ankle, a->landmarks.right_ankle);
    EXPECT_EQ(b->landmarks.pelvis, a->landmarks.pelvis);
    EXPECT_EQ(b->landmarks.head, a->landmarks.head);
    EXPECT_EQ(b->group_of_joint, a->group_of_joint);
    EXPECT_FLOAT_EQ(b->leg_length, a->leg_length);
  }
}

// Rotates the whole clip about the vertical and moves it on the ground.
LocalMotion Placed(LocalMotion motion, float yaw_radians, const Eigen::Vector3f& ground_shift) {
  RotateWorld(motion, Eigen::Quaternionf(Eigen::AngleAxisf(yaw_radians, Eigen::Vector3f::UnitY())));
  for (int f = 0; f < motion.num_frames(); ++f) {
    motion.SetTranslation(f, 0, motion.translation(f, 0) + ground_shift);
  }
  return motion;
}

TEST(BodyTopologyTest, InvariantUnderRotationAboutVerticalAndGroundTranslation) {
  for (int bits : {0, 1, 2, 4 | 8, 31}) {
    const SyntheticRigOptions options = RigFromBits(bits);
    SCOPED_TRACE(Describe(options));
    const BvhClip clip = MakeWalkingClip(options, 30);
    const LocalMotion motion = MotionFromChannels(clip.skeleton, clip.channels, clip.frame_time);
    const absl::StatusOr<BodyTopology> a = AnalyseBody(clip.skeleton, motion);
    ASSERT_TRUE(a.ok()) << a.status();
    for (float yaw : {0.7f, 2.5f, -1.9f}) {
      SCOPED_TRACE(yaw);
      const absl::StatusOr<BodyTopology> b =
          AnalyseBody(clip.skeleton, Placed(motion, yaw, Eigen::Vector3f(-230.0f, 0.0f, 145.0f)));
      ASSERT_TRUE(b.ok()) << b.status();
      ExpectSyntheticLandmarks(clip.skeleton, b->landmarks);
      EXPECT_EQ(b->group_of_joint, a->group_of_joint);
      EXPECT_EQ(b->up_axis, 1);
      EXPECT_EQ(b->up_sign, 1);
      EXPECT_NEAR(b->leg_length, a->leg_length, 1e-3f);
      EXPECT_NEAR(b->standing_pelvis_height, a->standing_pelvis_height, 1e-2f);
      EXPECT_NEAR(b->floor_height, a->floor_height, 1e-2f);
      // The facing direction turns with the clip.
      const Eigen::Vector3f expected_forward = Eigen::AngleAxisf(yaw, Eigen::Vector3f::UnitY()) * a->forward;
      EXPECT_GT(b->forward.dot(expected_forward), 0.999f) << b->forward.transpose();
    }
  }
}

// The mirror image (x -> -x) of a clip: "Left*" joints end up on the character's right.
void Mirror(Skeleton* skeleton, LocalMotion* motion) {
  std::vector<Joint> joints = skeleton->joints();
  for (Joint& joint : joints) {
    joint.offset.x() = -joint.offset.x();
    if (joint.end_site) joint.end_site->x() = -joint.end_site->x();
  }
  *skeleton = Skeleton(std::move(joints));
  motion->tx = -motion->tx;
  motion->qy = -motion->qy;
  motion->qz = -motion->qz;
}

TEST(BodyTopologyTest, MirrorImageSwapsLeftAndRight) {
  for (int bits : {0, 4 | 8, 1 | 16}) {
    const SyntheticRigOptions options = RigFromBits(bits);
    SCOPED_TRACE(Describe(options));
    const BvhClip clip = MakeWalkingClip(options, 30);
    Skeleton skeleton = clip.skeleton;
    LocalMotion motion = MotionFromChannels(clip.skeleton, clip.channels, clip.frame_time);
    Mirror(&skeleton, &motion);
    // Sanity check of the mirror itself: LeftHand is now at -X.
    const GlobalPoses poses = ForwardKinematics(skeleton, motion);
    ASSERT_LT(poses.position(0, Find(skeleton, "LeftHand")).x(), -10.0f);
    const absl::StatusOr<BodyTopology> topology = AnalyseBody(skeleton, motion);
    ASSERT_TRUE(topology.ok()) << topology.status();
    EXPECT_EQ(NameOf(skeleton, topology->landmarks.left_wrist), "RightHand");
    EXPECT_EQ(NameOf(skeleton, topology->landmarks.right_wrist), "LeftHand");
    EXPECT_EQ(NameOf(skeleton, topology->landmarks.left_ankle), "RightFoot");
    EXPECT_EQ(NameOf(skeleton, topology->landmarks.right_ankle), "LeftFoot");
    EXPECT_EQ(NameOf(skeleton, topology->landmarks.pelvis), "Hips");
    EXPECT_EQ(NameOf(skeleton, topology->landmarks.head), "Head");
    EXPECT_EQ(topology->group_of_joint[Find(skeleton, "LeftUpLeg")], BodyGroup::kRightLeg);
    EXPECT_EQ(topology->group_of_joint[Find(skeleton, "RightShoulder")], BodyGroup::kLeftArm);
    EXPECT_GT(topology->forward.z(), 0.95f);
  }
}

TEST(BodyTopologyTest, SingleRestFrameOfAPlainRig) {
  // One frame of the zero-rotation T-pose: knees straight, but the toes point forward.
  const BvhClip clip = MakeWalkingClip({}, 1);
  const Skeleton& skeleton = clip.skeleton;
  const absl::StatusOr<BodyTopology> topology = AnalyseBody(skeleton, RestMotion(skeleton));
  ASSERT_TRUE(topology.ok()) << topology.status();
  ExpectSyntheticLandmarks(skeleton, topology->landmarks);
  EXPECT_EQ(topology->up_axis, 1);
  EXPECT_GT(topology->forward.z(), 0.99f);
  // Rest pose: ankles 5 cm up, toes 0.5 cm, hips at 96 cm.
  EXPECT_NEAR(topology->floor_height, testing::kSyntheticToeHeight, 1e-3);
  EXPECT_NEAR(topology->standing_pelvis_height, testing::kSyntheticRestHipsHeight - testing::kSyntheticToeHeight, 1e-3);
}

// ---------------------------------------------------------------------------------------------
// Rigs and clips of other exporters (issue 23): long clavicles, walks that turn, go backwards or
// sideways, names that lie, one-frame T- and A-poses, with and without twist bones and fingers.
// Sides and limb segments come from evidence that holds frame by frame, never from a clip's mean.

using testing::MakeStandingClip;
using testing::SyntheticPath;

// Every landmark of the synthetic rig, by the names MakeWalkingClip gives; with `names_lie` (the
// rig's mirrored_names) the joint on the body's left is named "Right*" and the reverse.
void ExpectEveryLandmark(const Skeleton& skeleton, const BodyLandmarks& l, bool names_lie = false) {
  const std::string left = names_lie ? "Right" : "Left", right = names_lie ? "Left" : "Right";
  EXPECT_EQ(NameOf(skeleton, l.pelvis), "Hips");
  EXPECT_EQ(NameOf(skeleton, l.head), "Head");
  for (const auto& [side, wrist, elbow, shoulder, ankle, knee, hip] :
       {std::tuple{left, l.left_wrist, l.left_elbow, l.left_shoulder, l.left_ankle, l.left_knee, l.left_hip},
        std::tuple{right, l.right_wrist, l.right_elbow, l.right_shoulder, l.right_ankle, l.right_knee, l.right_hip}}) {
    EXPECT_EQ(NameOf(skeleton, wrist), side + "Hand");
    EXPECT_EQ(NameOf(skeleton, elbow), side + "ForeArm");
    EXPECT_EQ(NameOf(skeleton, shoulder), side + "Arm");  // past the clavicle
    EXPECT_EQ(NameOf(skeleton, ankle), side + "Foot");
    EXPECT_EQ(NameOf(skeleton, knee), side + "Leg");
    EXPECT_EQ(NameOf(skeleton, hip), side + "UpLeg");
  }
}

// Rig variants each case runs on: plain; fingers, toes and twist bones; everything (extra root,
// Z-up, position channels on every joint too).
constexpr int kRigVariants[] = {0, 4 | 8, 31};

TEST(BodyTopologyOtherRigsTest, ClavicleLongerThanTheForearm) {
  // The CMU 31-joint rig's clavicle is longer than its forearm (here 25), shorter than its upper
  // arm (28): the two longest segments are then clavicle and upper arm.
  for (double clavicle : {26.0, 27.5}) {
    for (int bits : kRigVariants) {
      SyntheticRigOptions options = RigFromBits(bits);
      options.clavicle_length = clavicle;
      SCOPED_TRACE(Describe(options) + " clavicle " + std::to_string(clavicle));
      const BvhClip clip = MakeWalkingClip(options, 40);
      const absl::StatusOr<BodyTopology> topology = Analyse(clip);
      ASSERT_TRUE(topology.ok()) << topology.status();
      ExpectEveryLandmark(clip.skeleton, topology->landmarks);
      // The same rig standing in a one-frame T-pose: no motion at all to tell the bones apart.
      const BvhClip t_pose = MakeStandingClip(options, 0.0);
      const absl::StatusOr<BodyTopology> standing = Analyse(t_pose);
      ASSERT_TRUE(standing.ok()) << standing.status();
      ExpectEveryLandmark(t_pose.skeleton, standing->landmarks);
    }
  }
}

// Frames of a synthetic walk in a circle of `radius` cm that make exactly `turns` whole turns.
int FramesForTurns(double radius, double turns) {
  return static_cast<int>(std::round(turns * 2 * M_PI * std::abs(radius) / testing::kSyntheticWalkSpeed * 30));
}

TEST(BodyTopologyOtherRigsTest, WalkInACircle) {
  // Over two whole turns the mean facing direction is nothing (the analysis before issue 23 summed
  // the knee and toe cues over the clip: it swapped every side turning left and the arms alone
  // turning right); every frame still has a front. Turning left and turning right.
  for (double radius : {150.0, -150.0}) {
    for (int bits : kRigVariants) {
      SyntheticRigOptions options = RigFromBits(bits);
      options.path = SyntheticPath::kCircle;
      options.circle_radius = radius;
      SCOPED_TRACE(Describe(options) + " radius " + std::to_string(radius));
      const BvhClip clip = MakeWalkingClip(options, FramesForTurns(radius, 2.0), 1.0 / 30);
      // The clip does turn: the hips face every way (the sanity check of the clip itself).
      const GlobalPoses poses =
          ForwardKinematics(clip.skeleton, MotionFromChannels(clip.skeleton, clip.channels, clip.frame_time));
      const int left_hip = Find(clip.skeleton, "LeftUpLeg"), right_hip = Find(clip.skeleton, "RightUpLeg");
      Eigen::Vector3f mean_hip_line = Eigen::Vector3f::Zero();
      for (int f = 0; f < poses.num_frames(); ++f) {
        mean_hip_line += (poses.position(f, left_hip) - poses.position(f, right_hip)).normalized();
      }
      ASSERT_LT(mean_hip_line.norm() / poses.num_frames(), 0.2f);
      const absl::StatusOr<BodyTopology> topology = Analyse(clip);
      ASSERT_TRUE(topology.ok()) << topology.status();
      ExpectEveryLandmark(clip.skeleton, topology->landmarks);
    }
  }
}

TEST(BodyTopologyOtherRigsTest, WalkingBackwardsAndSideStepping) {
  for (SyntheticPath path : {SyntheticPath::kBackwards, SyntheticPath::kSideways}) {
    for (int bits : kRigVariants) {
      SyntheticRigOptions options = RigFromBits(bits);
      options.path = path;
      SCOPED_TRACE(Describe(options) + (path == SyntheticPath::kBackwards ? " backwards" : " sideways"));
      const BvhClip clip = MakeWalkingClip(options, 60);
      const absl::StatusOr<BodyTopology> topology = Analyse(clip);
      ASSERT_TRUE(topology.ok()) << topology.status();
      ExpectEveryLandmark(clip.skeleton, topology->landmarks);
      // It faces +Z whichever way it travels.
      EXPECT_GT(topology->forward.z(), 0.95f) << topology->forward.transpose();
    }
  }
}

TEST(BodyTopologyOtherRigsTest, NamesThatLieAreIgnored) {
  // Every "Left*" joint named "Right*" and the reverse: the landmarks follow the body, not the
  // names, in a straight walk, a circle and a T-pose.
  for (int bits : kRigVariants) {
    SyntheticRigOptions options = RigFromBits(bits);
    options.mirrored_names = true;
    SCOPED_TRACE(Describe(options));
    const BvhClip clip = MakeWalkingClip(options, 40);
    ASSERT_GT(ForwardKinematics(clip.skeleton, MotionFromChannels(clip.skeleton, clip.channels, clip.frame_time))
                  .position(0, Find(clip.skeleton, "RightHand"))
                  .x(),
              10.0f);  // the "RightHand" is on the body's left (+X)
    absl::StatusOr<BodyTopology> topology = Analyse(clip);
    ASSERT_TRUE(topology.ok()) << topology.status();
    ExpectEveryLandmark(clip.skeleton, topology->landmarks, /*names_lie=*/true);
    EXPECT_EQ(topology->group_of_joint[Find(clip.skeleton, "RightUpLeg")], BodyGroup::kLeftLeg);

    options.path = SyntheticPath::kCircle;
    options.circle_radius = 150.0;
    const BvhClip circle = MakeWalkingClip(options, FramesForTurns(150.0, 2.0));
    topology = Analyse(circle);
    ASSERT_TRUE(topology.ok()) << topology.status();
    ExpectEveryLandmark(circle.skeleton, topology->landmarks, /*names_lie=*/true);

    const BvhClip t_pose = MakeStandingClip(options, 0.0);
    topology = Analyse(t_pose);
    ASSERT_TRUE(topology.ok()) << topology.status();
    ExpectEveryLandmark(t_pose.skeleton, topology->landmarks, /*names_lie=*/true);
  }
}

TEST(BodyTopologyOtherRigsTest, OneFrameTPoseAndAPose) {
  for (double arm_lowering : {0.0, 45.0}) {
    for (int bits : kRigVariants) {
      const SyntheticRigOptions options = RigFromBits(bits);
      SCOPED_TRACE(Describe(options) + (arm_lowering == 0.0 ? " T-pose" : " A-pose"));
      const BvhClip clip = MakeStandingClip(options, arm_lowering);
      ASSERT_EQ(clip.channels.rows(), 1);
      const absl::StatusOr<BodyTopology> topology = Analyse(clip);
      ASSERT_TRUE(topology.ok()) << topology.status();
      ExpectEveryLandmark(clip.skeleton, topology->landmarks);
      EXPECT_EQ(topology->up_axis, 1);
      EXPECT_EQ(topology->up_sign, 1);
      EXPECT_GT(topology->forward.z(), 0.99f) << topology->forward.transpose();  // the toes point forward
    }
  }
}

TEST(BodyTopologyOtherRigsTest, EverythingAtOnce) {
  // Long clavicles, lying names, twist bones, fingers and toes, a Z-up hierarchy under an extra
  // root, walking a circle to the right: each cue holds in every frame, so they do not interfere.
  SyntheticRigOptions options = RigFromBits(31, "YZX");
  options.clavicle_length = 27.0;
  options.mirrored_names = true;
  options.path = SyntheticPath::kCircle;
  options.circle_radius = -150.0;
  const BvhClip clip = MakeWalkingClip(options, FramesForTurns(-150.0, 2.0));
  const absl::StatusOr<BodyTopology> topology = Analyse(clip);
  ASSERT_TRUE(topology.ok()) << topology.status();
  ExpectEveryLandmark(clip.skeleton, topology->landmarks, /*names_lie=*/true);
}

// ---------------------------------------------------------------------------------------------
// Failure cases.

Skeleton ChainSkeleton(int joints) {
  std::vector<Joint> out;
  for (int j = 0; j < joints; ++j) {
    out.push_back(Joint{.name = "Bone" + std::to_string(j),
                        .parent = j - 1,
                        .offset = j == 0 ? Eigen::Vector3f(0, 90, 0) : Eigen::Vector3f(0, 20, 0)});
  }
  return Skeleton(std::move(out));
}

TEST(BodyTopologyTest, ChainIsNotAHumanoid) {
  const Skeleton chain = ChainSkeleton(8);
  const absl::StatusOr<BodyTopology> topology = AnalyseBody(chain, RestMotion(chain));
  ASSERT_FALSE(topology.ok());
  EXPECT_EQ(topology.status().code(), absl::StatusCode::kFailedPrecondition) << topology.status();
  EXPECT_NE(topology.status().message().find("limb ends"), std::string_view::npos) << topology.status();
  EXPECT_NE(topology.status().message().find("five"), std::string_view::npos) << topology.status();
}

TEST(BodyTopologyTest, FourLimbsAreNotAHumanoid) {
  // A root with four two-bone limbs: four limb ends.
  std::vector<Joint> joints = {Joint{.name = "Root", .parent = -1, .offset = {0, 90, 0}}};
  const Eigen::Vector3f directions[4] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
  for (int limb = 0; limb < 4; ++limb) {
    const int top = static_cast<int>(joints.size());
    joints.push_back(Joint{.name = "A" + std::to_string(limb), .parent = 0, .offset = 10 * directions[limb]});
    joints.push_back(Joint{.name = "B" + std::to_string(limb), .parent = top, .offset = 30 * directions[limb]});
    joints.push_back(Joint{.name = "C" + std::to_string(limb), .parent = top + 1, .offset = 30 * directions[limb]});
  }
  const Skeleton skeleton(std::move(joints));
  ASSERT_TRUE(skeleton.Validate().ok());
  const absl::StatusOr<BodyTopology> topology = AnalyseBody(skeleton, RestMotion(skeleton));
  ASSERT_FALSE(topology.ok());
  EXPECT_EQ(topology.status().code(), absl::StatusCode::kFailedPrecondition) << topology.status();
  EXPECT_NE(topology.status().message().find("4 limb ends"), std::string_view::npos) << topology.status();
}

TEST(BodyTopologyTest, MotionOfTheWrongSizeIsRefused) {
  const BvhClip clip = MakeWalkingClip({}, 5);
  const Skeleton chain = ChainSkeleton(4);
  const absl::StatusOr<BodyTopology> topology = AnalyseBody(clip.skeleton, RestMotion(chain));
  EXPECT_FALSE(topology.ok());
}

// The synthetic rig without its toe bases; with `foot_end_sites`, each foot (then a leaf) keeps
// the toes as its End Site, as rigs whose feet end at the ankle joint draw them.
Skeleton WithoutToeJoints(bool foot_end_sites) {
  const BvhClip clip = MakeWalkingClip({}, 1);
  std::vector<Joint> joints;
  std::vector<int> new_index(clip.skeleton.num_joints(), -1);
  for (int j = 0; j < clip.skeleton.num_joints(); ++j) {
    Joint joint = clip.skeleton.joint(j);
    if (joint.name.find("ToeBase") != std::string::npos) continue;
    if (foot_end_sites && joint.name.find("Foot") != std::string::npos) joint.end_site = Eigen::Vector3f(0, -4.5f, 13);
    joint.parent = joint.parent < 0 ? -1 : new_index[joint.parent];
    new_index[j] = static_cast<int>(joints.size());
    joints.push_back(std::move(joint));
  }
  return Skeleton(std::move(joints));
}

TEST(BodyTopologyTest, StandingStillWithToesOnlyAsEndSites) {
  // One frame of the straight-legged rest pose, the feet ending at the ankle joints: the End Sites
  // still say where the toes point.
  const Skeleton skeleton = WithoutToeJoints(/*foot_end_sites=*/true);
  ASSERT_TRUE(skeleton.Validate().ok());
  const absl::StatusOr<BodyTopology> topology = AnalyseBody(skeleton, RestMotion(skeleton));
  ASSERT_TRUE(topology.ok()) << topology.status();
  ExpectSyntheticLandmarks(skeleton, topology->landmarks);
  EXPECT_GT(topology->forward.z(), 0.99f) << topology->forward.transpose();
}

TEST(BodyTopologyTest, StandingStillWithoutToesCannotTellLeftFromRight) {
  // The synthetic rig without toe bases, one frame of the straight-legged rest pose: no knee bend,
  // no toes and no travel.
  const Skeleton skeleton = WithoutToeJoints(/*foot_end_sites=*/false);
  ASSERT_TRUE(skeleton.Validate().ok());
  const absl::StatusOr<BodyTopology> topology = AnalyseBody(skeleton, RestMotion(skeleton));
  ASSERT_FALSE(topology.ok()) << "forward " << topology->forward.transpose() << ", left wrist "
                              << NameOf(skeleton, topology->landmarks.left_wrist);
  EXPECT_EQ(topology.status().code(), absl::StatusCode::kFailedPrecondition) << topology.status();
  EXPECT_NE(topology.status().message().find("left from right"), std::string_view::npos) << topology.status();
}

// ---------------------------------------------------------------------------------------------
// Real data.

struct RealClip {
  std::string set;
  std::string file;
};

void PrintTo(const RealClip& clip, std::ostream* os) { *os << clip.set << "/" << clip.file; }

class BodyTopologySharedDataTest : public ::testing::TestWithParam<RealClip> {};

TEST_P(BodyTopologySharedDataTest, StandingHeightAndFloor) {
  MOCAP_REQUIRE_SHARED_DATA(folder, GetParam().set);
  const absl::StatusOr<BvhClip> clip = ReadBvhFile(folder / GetParam().file);
  ASSERT_TRUE(clip.ok()) << clip.status();
  const absl::StatusOr<BodyTopology> topology = Analyse(*clip);
  ASSERT_TRUE(topology.ok()) << topology.status();
  EXPECT_EQ(topology->unit, LengthUnit::kCentimetre);
  EXPECT_EQ(topology->up_axis, 1);
  EXPECT_EQ(topology->up_sign, 1);
  const double metres = MetresPerUnit(topology->unit);
  EXPECT_GT(topology->standing_pelvis_height * metres, 0.8);
  EXPECT_LT(topology->standing_pelvis_height * metres, 1.15);
  // floor_height is the lowest joint centre: the toe joints of both rigs sit 4-6 cm above the
  // ground the clips stand on (y = 0), inside the foot. It must stay near the ground.
  EXPECT_GT(topology->floor_height * metres, -0.03);
  EXPECT_LT(topology->floor_height * metres, 0.08);
  const BodyLandmarks& l = topology->landmarks;
  for (int joint : {l.pelvis, l.head, l.left_wrist, l.right_wrist, l.left_ankle, l.right_ankle}) {
    ASSERT_GE(joint, 0);
    ASSERT_LT(joint, clip->skeleton.num_joints());
  }
  // Every landmark is distinct.
  std::vector<int> all = {l.pelvis, l.head, l.left_wrist, l.right_wrist, l.left_ankle, l.right_ankle};
  std::sort(all.begin(), all.end());
  EXPECT_EQ(std::unique(all.begin(), all.end()), all.end());
}

INSTANTIATE_TEST_SUITE_P(Files, BodyTopologySharedDataTest,
                         ::testing::Values(RealClip{"bandai-namco-2", "dataset-2_walk_normal_001.bvh"},
                                           RealClip{"bandai-namco-2", "dataset-2_raise-up-both-hands_active_001.bvh"},
                                           RealClip{"bandai-namco-1", "dataset-1_bow_active_001.bvh"},
                                           RealClip{"cmu-cc", "002_01.bvh"}, RealClip{"cmu-cc", "007_01.bvh"},
                                           RealClip{"cmu-cc", "005_01.bvh"}),
                         [](const ::testing::TestParamInfo<RealClip>& info) {
                           std::string name = info.param.set + "_" + info.param.file;
                           for (char& c : name) {
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           }
                           return name;
                         });

TEST(BodyTopologySharedDataTest, AnklesAreLowestLandmarksOnBandaiWalks) {
  MOCAP_REQUIRE_SHARED_DATA(folder, "bandai-namco-2");
  int files = 0;
  for (const char* name :
       {"dataset-2_walk_normal_001.bvh", "dataset-2_walk_elderly_001.bvh", "dataset-2_walk-turn-left_active_001.bvh"}) {
    SCOPED_TRACE(name);
    const absl::StatusOr<BvhClip> clip = ReadBvhFile(folder / name);
    if (!clip.ok()) continue;  // a held-out take
    ++files;
    const LocalMotion motion = MotionFromChannels(clip->skeleton, clip->channels, clip->frame_time);
    const absl::StatusOr<BodyTopology> topology = AnalyseBody(clip->skeleton, motion);
    ASSERT_TRUE(topology.ok()) << topology.status();
    const GlobalPoses poses = ForwardKinematics(clip->skeleton, motion);
    const BodyLandmarks& l = topology->landmarks;
    const Eigen::Vector3f up = topology->up();
    int ankle_lowest = 0, planted_near_floor = 0;
    for (int f = 0; f < poses.num_frames(); ++f) {
      auto height = [&](int joint) { return poses.position(f, joint).dot(up); };
      const float ankle = std::min(height(l.left_ankle), height(l.right_ankle));
      const float other = std::min({height(l.pelvis), height(l.head), height(l.left_wrist), height(l.right_wrist)});
      if (ankle < other) ++ankle_lowest;
      // The lower ankle of a walk is within 20 cm of the floor (the stance foot).
      if (ankle - topology->floor_height < 20.0f) ++planted_near_floor;
    }
    EXPECT_GT(ankle_lowest, 0.9 * poses.num_frames());
    EXPECT_GT(planted_near_floor, 0.9 * poses.num_frames());
  }
  EXPECT_GT(files, 0);
}

// Every file of every shared set, turned about the vertical at a steady rate, two whole turns over
// the clip (what a walk in a circle looks like to a clip mean: no facing at all), keeps every
// landmark; mirrored (x -> -x, so that its names lie), swaps every side. Before issue 23 the turn
// alone changed the sides of 17 of 45 cmu-cc and 51 of 174 bandai-namco-1 files.
class BodyTopologyEveryFileTest : public ::testing::TestWithParam<const char*> {};

TEST_P(BodyTopologyEveryFileTest, TurnedKeepsAndMirroredSwapsEveryLandmark) {
  MOCAP_REQUIRE_SHARED_DATA(folder, GetParam());
  int files = 0;
  for (const auto& file : testing::BvhFilesIn(folder)) {
    SCOPED_TRACE(file.filename().string());
    const absl::StatusOr<BvhClip> clip = ReadBvhFile(file);
    ASSERT_TRUE(clip.ok()) << clip.status();
    const LocalMotion motion = MotionFromChannels(clip->skeleton, clip->channels, clip->frame_time);
    const absl::StatusOr<BodyTopology> original = AnalyseBody(clip->skeleton, motion);
    ASSERT_TRUE(original.ok()) << original.status();
    const BodyLandmarks& a = original->landmarks;
    ++files;

    LocalMotion turned = motion;
    const int frames = turned.num_frames();
    for (int f = 0; f < frames; ++f) {
      const float yaw = frames > 1 ? 4.0f * static_cast<float>(M_PI) * f / (frames - 1) : 0.0f;
      const Eigen::Quaternionf turn(Eigen::AngleAxisf(yaw, original->up()));
      turned.SetRotation(f, 0, (turn * turned.rotation(f, 0)).normalized());
      turned.SetTranslation(f, 0, turn * turned.translation(f, 0));
    }
    const absl::StatusOr<BodyTopology> spun = AnalyseBody(clip->skeleton, turned);
    ASSERT_TRUE(spun.ok()) << spun.status();
    const BodyLandmarks& b = spun->landmarks;
    for (const auto& [x, y] : {std::pair{a.left_wrist, b.left_wrist},
                               {a.right_wrist, b.right_wrist},
                               {a.left_elbow, b.left_elbow},
                               {a.left_shoulder, b.left_shoulder},
                               {a.left_ankle, b.left_ankle},
                               {a.right_ankle, b.right_ankle},
                               {a.left_knee, b.left_knee},
                               {a.left_hip, b.left_hip},
                               {a.head, b.head},
                               {a.pelvis, b.pelvis}}) {
      EXPECT_EQ(NameOf(clip->skeleton, y), NameOf(clip->skeleton, x)) << "turned";
    }

    Skeleton mirrored = clip->skeleton;
    LocalMotion mirrored_motion = motion;
    Mirror(&mirrored, &mirrored_motion);
    const absl::StatusOr<BodyTopology> mirror = AnalyseBody(mirrored, mirrored_motion);
    ASSERT_TRUE(mirror.ok()) << mirror.status();
    const BodyLandmarks& c = mirror->landmarks;
    for (const auto& [x, y] : {std::pair{a.left_wrist, c.right_wrist},
                               {a.right_wrist, c.left_wrist},
                               {a.left_elbow, c.right_elbow},
                               {a.left_shoulder, c.right_shoulder},
                               {a.left_ankle, c.right_ankle},
                               {a.right_ankle, c.left_ankle},
                               {a.left_knee, c.right_knee},
                               {a.left_hip, c.right_hip},
                               {a.head, c.head},
                               {a.pelvis, c.pelvis}}) {
      EXPECT_EQ(NameOf(clip->skeleton, y), NameOf(clip->skeleton, x)) << "mirrored";
    }
  }
  EXPECT_GT(files, 0);
}

INSTANTIATE_TEST_SUITE_P(AllSets, BodyTopologyEveryFileTest,
                         ::testing::Values("bandai-namco-1", "bandai-namco-2", "cmu-cc", "other-rigs"),
                         [](const ::testing::TestParamInfo<const char*>& info) {
                           std::string name = info.param;
                           for (char& c : name) {
                             if (c == '-') c = '_';
                           }
                           return name;
                         });

}  // namespace
}  // namespace mocap

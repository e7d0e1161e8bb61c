#include "motion/skeleton/forward_kinematics.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "motion/skeleton/local_motion.h"
#include "tests/support/rotation_checks.h"
#include "tests/support/synthetic_clip.h"

namespace mocap {
namespace {

using testing::AngleBetween;
using testing::kDegree;

Eigen::Quaternionf AxisAngle(float degrees, const Eigen::Vector3f& axis) {
  return Eigen::Quaternionf(Eigen::AngleAxisf(degrees * kDegree, axis.normalized()));
}

Skeleton Chain(const std::vector<Eigen::Vector3f>& offsets) {
  std::vector<Joint> joints;
  for (size_t i = 0; i < offsets.size(); ++i) {
    joints.push_back(Joint{.name = "J" + std::to_string(i), .parent = static_cast<int>(i) - 1, .offset = offsets[i]});
  }
  return Skeleton(std::move(joints));
}

TEST(ForwardKinematicsTest, TwoJointChainByHand) {
  const Skeleton skeleton = Chain({{1, 2, 3}, {1, 0, 0}});
  LocalMotion motion = RestMotion(skeleton);
  ASSERT_EQ(motion.num_frames(), 1);
  motion.SetRotation(0, 0, AxisAngle(90, Eigen::Vector3f::UnitZ()));
  const GlobalPoses poses = ForwardKinematics(skeleton, motion);
  ASSERT_EQ(poses.num_frames(), 1);
  ASSERT_EQ(poses.num_joints(), 2);
  EXPECT_TRUE(poses.position(0, 0).isApprox(Eigen::Vector3f(1, 2, 3)));
  // Rz(90) (1, 0, 0) = (0, 1, 0).
  EXPECT_LT((poses.position(0, 1) - Eigen::Vector3f(1, 3, 3)).norm(), 1e-6f);
  EXPECT_LT(AngleBetween(poses.rotation(0, 1), AxisAngle(90, Eigen::Vector3f::UnitZ())), 1e-6);
}

TEST(ForwardKinematicsTest, ThreeJointChainByHand) {
  const Skeleton skeleton = Chain({{0, 0, 0}, {0, 0, 2}, {0, 0, 1}});
  LocalMotion motion = RestMotion(skeleton);
  motion.SetRotation(0, 0, AxisAngle(45, Eigen::Vector3f::UnitY()));
  motion.SetRotation(0, 1, AxisAngle(-90, Eigen::Vector3f::UnitX()));
  const GlobalPoses poses = ForwardKinematics(skeleton, motion);
  const float r = std::sqrt(2.0f);
  // Ry(45) (0, 0, 2) = (sqrt2, 0, sqrt2); Rx(-90) (0, 0, 1) = (0, 1, 0), which Ry leaves alone.
  EXPECT_LT((poses.position(0, 1) - Eigen::Vector3f(r, 0, r)).norm(), 1e-6f);
  EXPECT_LT((poses.position(0, 2) - Eigen::Vector3f(r, 1, r)).norm(), 1e-6f);
  EXPECT_LT(AngleBetween(poses.rotation(0, 2),
                         AxisAngle(45, Eigen::Vector3f::UnitY()) * AxisAngle(-90, Eigen::Vector3f::UnitX())),
            1e-6);
}

TEST(ForwardKinematicsTest, ChainThroughBvhChannels) {
  // Root at OFFSET (0, 10, 0) + channels (5, 0, 0), rotated 90 deg about Y (ZXY order);
  // child 2 along +X rotated 90 deg about Z; grandchild 3 along +X.
  std::vector<Joint> joints;
  joints.push_back(Joint{.name = "Root",
                         .parent = -1,
                         .offset = Eigen::Vector3f(0, 10, 0),
                         .channels = {ChannelType::kXposition, ChannelType::kYposition, ChannelType::kZposition,
                                      ChannelType::kZrotation, ChannelType::kXrotation, ChannelType::kYrotation}});
  joints.push_back(Joint{.name = "Arm",
                         .parent = 0,
                         .offset = Eigen::Vector3f(2, 0, 0),
                         .channels = {ChannelType::kZrotation, ChannelType::kXrotation, ChannelType::kYrotation}});
  joints.push_back(Joint{.name = "Hand", .parent = 1, .offset = Eigen::Vector3f(3, 0, 0)});
  const Skeleton skeleton(std::move(joints));
  ChannelMatrix channels(1, 9);
  channels << 5, 0, 0, 0, 0, 90, 90, 0, 0;
  const GlobalPoses poses = ForwardKinematics(skeleton, MotionFromChannels(skeleton, channels, 1.0 / 30));
  // Root (5, 10, 0); Ry(90) (2, 0, 0) = (0, 0, -2); Ry(90) Rz(90) (3, 0, 0) = Ry(90) (0, 3, 0) = (0, 3, 0).
  EXPECT_LT((poses.position(0, 0) - Eigen::Vector3f(5, 10, 0)).norm(), 1e-5f);
  EXPECT_LT((poses.position(0, 1) - Eigen::Vector3f(5, 10, -2)).norm(), 1e-5f);
  EXPECT_LT((poses.position(0, 2) - Eigen::Vector3f(5, 13, -2)).norm(), 1e-5f);
}

// Forward kinematics straight from the BVH channels with Eigen transforms, one frame at a time.
std::vector<Eigen::Affine3f> NaiveForwardKinematics(const Skeleton& skeleton, const ChannelMatrix& channels,
                                                    int frame) {
  std::vector<Eigen::Affine3f> world(skeleton.num_joints());
  for (int j = 0; j < skeleton.num_joints(); ++j) {
    const Joint& joint = skeleton.joint(j);
    Eigen::Vector3f translation = joint.offset;
    Eigen::Matrix3f rotation = Eigen::Matrix3f::Identity();
    for (size_t c = 0; c < joint.channels.size(); ++c) {
      const float value = channels(frame, skeleton.channel_start(j) + static_cast<int>(c));
      const int axis = ChannelAxis(joint.channels[c]);
      if (IsRotation(joint.channels[c])) {
        rotation = rotation * Eigen::AngleAxisf(value * kDegree, Eigen::Vector3f::Unit(axis)).toRotationMatrix();
      } else {
        translation[axis] = j == 0 ? joint.offset[axis] + value : value;
      }
    }
    Eigen::Affine3f local = Eigen::Affine3f::Identity();
    local.translate(translation);
    local.rotate(rotation);
    world[j] = joint.parent < 0 ? local : world[joint.parent] * local;
  }
  return world;
}

struct RigCase {
  std::string name;
  testing::SyntheticRigOptions options;
};

std::vector<RigCase> RigCases() {
  return {
      {"Plain", {}},
      {"ExtraRoot", {.extra_root = true}},
      {"ZUp", {.z_up = true}},
      {"FingersAndToes", {.fingers_and_toes = true}},
      {"TwistBones", {.twist_bones = true}},
      {"PositionChannelsEverywhere", {.position_channels_everywhere = true}},
      {"ZUpExtraRoot", {.extra_root = true, .z_up = true}},
      {"ZUpEverywhere", {.z_up = true, .position_channels_everywhere = true}},
      {"Metres", {.length_scale = 0.01}},
      {"Inches", {.length_scale = 1 / 2.54}},
      {"OrderXYZ", {.rotation_order = "XYZ"}},
      {"OrderXZY", {.rotation_order = "XZY"}},
      {"OrderYXZ", {.rotation_order = "YXZ"}},
      {"OrderYZX", {.rotation_order = "YZX"}},
      {"OrderZYX", {.rotation_order = "ZYX"}},
      {"Everything",
       {.extra_root = true,
        .z_up = true,
        .fingers_and_toes = true,
        .twist_bones = true,
        .position_channels_everywhere = true,
        .length_scale = 0.01,
        .rotation_order = "YXZ"}},
  };
}

class ForwardKinematicsSyntheticTest : public ::testing::TestWithParam<RigCase> {};

TEST_P(ForwardKinematicsSyntheticTest, MatchesNaiveEigenChain) {
  const testing::SyntheticRigOptions& options = GetParam().options;
  const BvhClip clip = testing::MakeWalkingClip(options, 40);
  const LocalMotion motion = MotionFromChannels(clip.skeleton, clip.channels, clip.frame_time);
  const GlobalPoses poses = ForwardKinematics(clip.skeleton, motion);
  ASSERT_EQ(poses.num_frames(), 40);
  ASSERT_EQ(poses.num_joints(), clip.skeleton.num_joints());
  const float scale = static_cast<float>(100 * options.length_scale);  // about a metre
  for (int f = 0; f < clip.num_frames(); ++f) {
    const std::vector<Eigen::Affine3f> naive = NaiveForwardKinematics(clip.skeleton, clip.channels, f);
    for (int j = 0; j < clip.skeleton.num_joints(); ++j) {
      const Eigen::Vector3f expected = naive[j].translation();
      EXPECT_LE((poses.position(f, j) - expected).norm(), 1e-4f * std::max(scale, expected.norm()))
          << "frame " << f << " joint " << clip.skeleton.joint(j).name << ": " << poses.position(f, j).transpose()
          << " vs " << expected.transpose();
      EXPECT_LT(AngleBetween(poses.rotation(f, j), Eigen::Quaternionf(naive[j].rotation())), 1e-4)
          << "frame " << f << " joint " << clip.skeleton.joint(j).name;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(ForwardKinematicsRigs, ForwardKinematicsSyntheticTest, ::testing::ValuesIn(RigCases()),
                         [](const ::testing::TestParamInfo<RigCase>& info) { return info.param.name; });

TEST(ForwardKinematicsTest, RestMotionUsesOffsets) {
  const BvhClip clip = testing::MakeWalkingClip({}, 1);
  const LocalMotion rest = RestMotion(clip.skeleton);
  ASSERT_EQ(rest.num_frames(), 1);
  ASSERT_EQ(rest.num_joints(), clip.skeleton.num_joints());
  for (int j = 0; j < rest.num_joints(); ++j) {
    EXPECT_EQ(rest.translation(0, j), clip.skeleton.joint(j).offset);
    EXPECT_EQ(rest.rotation(0, j).coeffs(), Eigen::Quaternionf::Identity().coeffs());
  }
}

TEST(ForwardKinematicsTest, BoneLengths) {
  const Skeleton skeleton = Chain({{0, 0, 0}, {3, 4, 0}, {0, 0, 2}});
  LocalMotion motion;
  motion.Resize(2, 3);
  for (int f = 0; f < 2; ++f) {
    for (int j = 0; j < 3; ++j) {
      motion.SetRotation(f, j, Eigen::Quaternionf::Identity());
      motion.SetTranslation(f, j, skeleton.joint(j).offset);
    }
  }
  motion.SetTranslation(0, 0, Eigen::Vector3f(100, 100, 100));  // the root has no bone
  motion.SetTranslation(1, 2, Eigen::Vector3f(0, 6, 0));        // a stretching bone: mean of 2 and 6
  const Eigen::VectorXf lengths = BoneLengths(motion);
  ASSERT_EQ(lengths.size(), 3);
  EXPECT_EQ(lengths[0], 0.0f);
  EXPECT_FLOAT_EQ(lengths[1], 5.0f);
  EXPECT_FLOAT_EQ(lengths[2], 4.0f);
}

TEST(ForwardKinematicsTest, BoneLengthsOfTheSyntheticRig) {
  const BvhClip clip = testing::MakeWalkingClip({.position_channels_everywhere = true}, 10);
  const Eigen::VectorXf lengths = BoneLengths(MotionFromChannels(clip.skeleton, clip.channels, clip.frame_time));
  const Skeleton& s = clip.skeleton;
  EXPECT_EQ(lengths[0], 0.0f);
  EXPECT_FLOAT_EQ(lengths[s.Find("LeftLeg")], testing::kSyntheticThighLength);
  EXPECT_FLOAT_EQ(lengths[s.Find("RightFoot")], testing::kSyntheticShinLength);
  for (int j = 1; j < s.num_joints(); ++j) EXPECT_NEAR(lengths[j], s.joint(j).offset.norm(), 1e-4f) << s.joint(j).name;
}

// ---------------------------------------------------------------------------------------------
// The synthetic walking clip is what its header promises.

GlobalPoses Poses(const BvhClip& clip) {
  return ForwardKinematics(clip.skeleton, MotionFromChannels(clip.skeleton, clip.channels, clip.frame_time));
}

TEST(SyntheticClipTest, PlainRigJointNames) {
  const BvhClip clip = testing::MakeWalkingClip();
  const std::vector<std::string> expected = {
      "Hips",        "Spine",    "Chest",         "Neck",       "Head",         "LeftShoulder", "LeftArm",
      "LeftForeArm", "LeftHand", "RightShoulder", "RightArm",   "RightForeArm", "RightHand",    "LeftUpLeg",
      "LeftLeg",     "LeftFoot", "LeftToeBase",   "RightUpLeg", "RightLeg",     "RightFoot",    "RightToeBase"};
  ASSERT_EQ(clip.skeleton.num_joints(), static_cast<int>(expected.size()));
  for (int j = 0; j < clip.skeleton.num_joints(); ++j) EXPECT_EQ(clip.skeleton.joint(j).name, expected[j]);
  EXPECT_EQ(clip.num_frames(), 60);
  EXPECT_DOUBLE_EQ(clip.frame_time, 1.0 / 30);
  EXPECT_EQ(clip.skeleton.num_channels(), 6 + 3 * 20);
  const Skeleton& s = clip.skeleton;
  EXPECT_EQ(s.parent(s.Find("LeftUpLeg")), s.Find("Hips"));
  EXPECT_EQ(s.parent(s.Find("LeftShoulder")), s.Find("Chest"));
  EXPECT_EQ(s.parent(s.Find("RightHand")), s.Find("RightForeArm"));
}

TEST(SyntheticClipTest, RigOptionsShapeTheHierarchy) {
  {
    const Skeleton s = testing::MakeWalkingClip({.extra_root = true}, 2).skeleton;
    EXPECT_EQ(s.num_joints(), 22);
    EXPECT_EQ(s.joint(0).name, "Root");
    EXPECT_EQ(s.joint(0).offset, Eigen::Vector3f::Zero());
    EXPECT_EQ(s.joint(0).channels.size(), 6u);
    EXPECT_EQ(s.joint(1).name, "Hips");
    EXPECT_EQ(s.joint(1).channels.size(), 6u);
  }
  {
    const Skeleton s = testing::MakeWalkingClip({.z_up = true}, 2).skeleton;
    EXPECT_EQ(s.num_joints(), 22);
    EXPECT_EQ(s.joint(0).name, "RL_BoneRoot");
    EXPECT_EQ(s.joint(1).name, "Hips");
    EXPECT_EQ(s.joint(1).channels.size(), 3u);
    EXPECT_LT((s.joint(1).offset - Eigen::Vector3f(0, 0, testing::kSyntheticRestHipsHeight)).norm(), 1e-4f);
  }
  {
    const Skeleton s = testing::MakeWalkingClip({.fingers_and_toes = true}, 2).skeleton;
    EXPECT_EQ(s.num_joints(), 21 + 30 + 10);
    EXPECT_EQ(s.Children(s.Find("LeftHand")).size(), 5u);
    EXPECT_EQ(s.Children(s.Find("RightToeBase")).size(), 5u);
    EXPECT_EQ(s.parent(s.Find("LeftHandIndex3")), s.Find("LeftHandIndex2"));
    EXPECT_EQ(s.parent(s.Find("RightToe5")), s.Find("RightToeBase"));
  }
  {
    const Skeleton s = testing::MakeWalkingClip({.twist_bones = true}, 2).skeleton;
    EXPECT_EQ(s.num_joints(), 21 + 21);
    EXPECT_EQ(s.parent(s.Find("LeftUpLeg")), s.Find("Pelvis"));
    EXPECT_EQ(s.joint(s.Find("Pelvis")).offset, Eigen::Vector3f::Zero());
    EXPECT_EQ(s.joint(s.Find("LeftKneeShareBone")).offset, Eigen::Vector3f::Zero());
    EXPECT_EQ(s.parent(s.Find("LeftKneeShareBone")), s.Find("LeftLeg"));
    EXPECT_EQ(s.parent(s.Find("RightElbowShareBone")), s.Find("RightForeArm"));
    EXPECT_EQ(s.parent(s.Find("LeftUpLegTwistMid")), s.Find("LeftUpLegTwist"));
    EXPECT_EQ(s.Children(s.Find("LeftLeg")).size(), 3u);  // foot, twist, share bone
  }
  {
    const Skeleton s = testing::MakeWalkingClip({.position_channels_everywhere = true}, 2).skeleton;
    for (const Joint& joint : s.joints()) EXPECT_EQ(joint.channels.size(), 6u) << joint.name;
  }
  {
    const Skeleton s = testing::MakeWalkingClip({.rotation_order = "YXZ"}, 2).skeleton;
    const std::vector<ChannelType> yxz = {ChannelType::kYrotation, ChannelType::kXrotation, ChannelType::kZrotation};
    EXPECT_EQ(s.joint(1).channels, yxz);
    EXPECT_EQ(std::vector<ChannelType>(s.joint(0).channels.begin() + 3, s.joint(0).channels.end()), yxz);
  }
}

TEST(SyntheticClipTest, EveryRigIsValidWithEndSitesOnLeaves) {
  for (const RigCase& rig : RigCases()) {
    SCOPED_TRACE(rig.name);
    const BvhClip clip = testing::MakeWalkingClip(rig.options, 5);
    ASSERT_TRUE(clip.skeleton.Validate().ok()) << clip.skeleton.Validate();
    EXPECT_EQ(clip.channels.cols(), clip.skeleton.num_channels());
    EXPECT_TRUE(clip.channels.allFinite());
    for (int j = 0; j < clip.skeleton.num_joints(); ++j) {
      EXPECT_EQ(clip.skeleton.joint(j).end_site.has_value(), clip.skeleton.Children(j).empty())
          << clip.skeleton.joint(j).name;
    }
  }
}

TEST(SyntheticClipTest, RestPoseIsATPose) {
  const BvhClip clip = testing::MakeWalkingClip({}, 1);
  const GlobalPoses rest = ForwardKinematics(clip.skeleton, RestMotion(clip.skeleton));
  const Skeleton& s = clip.skeleton;
  auto at = [&](const char* name) { return rest.position(0, s.Find(name)); };
  EXPECT_LT((at("LeftHand") - Eigen::Vector3f(70, 138, 0)).norm(), 1e-4f);
  EXPECT_LT((at("RightHand") - Eigen::Vector3f(-70, 138, 0)).norm(), 1e-4f);
  EXPECT_NEAR(at("LeftFoot").y(), testing::kSyntheticAnkleHeight, 1e-4f);
  EXPECT_NEAR(at("RightToeBase").y(), testing::kSyntheticToeHeight, 1e-4f);
  EXPECT_GT(at("LeftToeBase").z(), at("LeftFoot").z());
  EXPECT_NEAR((at("LeftUpLeg") - at("LeftFoot")).norm(), testing::kSyntheticLegLength, 1e-4f);
  EXPECT_GT(at("Head").y(), at("Neck").y());
  EXPECT_GT(at("LeftArm").x(), 0);  // left at +X
}

TEST(SyntheticClipTest, WalksForwardWithFeetOnTheFloor) {
  const BvhClip clip = testing::MakeWalkingClip({}, 90);  // three gait cycles
  const GlobalPoses poses = Poses(clip);
  const Skeleton& s = clip.skeleton;
  const int hips = s.Find("Hips");
  const int ankles[2] = {s.Find("LeftFoot"), s.Find("RightFoot")};
  const int toes[2] = {s.Find("LeftToeBase"), s.Find("RightToeBase")};
  const double duration = (clip.num_frames() - 1) * clip.frame_time;
  EXPECT_NEAR((poses.pz(89, hips) - poses.pz(0, hips)) / duration, testing::kSyntheticWalkSpeed, 1e-3);
  EXPECT_LT(poses.px.col(hips).abs().maxCoeff(), 1e-3f);
  // Hips oscillate a little around ~92 cm.
  const float hips_low = poses.py.col(hips).minCoeff(), hips_high = poses.py.col(hips).maxCoeff();
  EXPECT_GT(hips_high - hips_low, 3.0f);
  EXPECT_LT(hips_high - hips_low, 10.0f);
  EXPECT_NEAR(poses.py.col(hips).mean(), 92, 4);
  for (int f = 0; f < clip.num_frames(); ++f) {
    // One ankle is always down; nothing goes below the floor.
    EXPECT_NEAR(std::min(poses.py(f, ankles[0]), poses.py(f, ankles[1])), testing::kSyntheticAnkleHeight, 1e-3f);
    EXPECT_GE(poses.py.row(f).minCoeff(), testing::kSyntheticToeHeight - 1e-3f) << f;
    EXPECT_NEAR(std::min(poses.py(f, toes[0]), poses.py(f, toes[1])), testing::kSyntheticToeHeight, 1e-3f);
    // Left at +X, facing +Z.
    EXPECT_GT(poses.px(f, s.Find("LeftUpLeg")), poses.px(f, s.Find("RightUpLeg")));
    EXPECT_GT(poses.px(f, s.Find("LeftHand")), poses.px(f, s.Find("RightHand")));
    const Eigen::Vector3f forward = poses.rotation(f, hips) * Eigen::Vector3f::UnitZ();
    EXPECT_GT(forward.z(), std::cos(5 * kDegree));
    const Eigen::Vector3f head_forward = poses.rotation(f, s.Find("Head")) * Eigen::Vector3f::UnitZ();
    EXPECT_GT(head_forward.z(), 0.9999f);
    for (int side = 0; side < 2; ++side) EXPECT_GT(poses.pz(f, toes[side]), poses.pz(f, ankles[side]));
  }
  for (int side = 0; side < 2; ++side) {
    // Swing: the ankle rises well clear of the floor.
    EXPECT_GT(poses.py.col(ankles[side]).maxCoeff(), testing::kSyntheticAnkleHeight + 5);
    // Planted feet do not slide.
    for (int f = 1; f < clip.num_frames(); ++f) {
      const bool down = poses.py(f - 1, ankles[side]) < testing::kSyntheticAnkleHeight + 1e-3f &&
                        poses.py(f, ankles[side]) < testing::kSyntheticAnkleHeight + 1e-3f;
      if (down) {
        EXPECT_LT((poses.position(f, ankles[side]) - poses.position(f - 1, ankles[side])).norm(), 0.05f)
            << "side " << side << " frame " << f;
      }
    }
  }
}

TEST(SyntheticClipTest, LegsAndArmsSwingInOpposition) {
  const BvhClip clip = testing::MakeWalkingClip({}, 61, 1.0 / 60);  // one gait cycle
  const GlobalPoses poses = Poses(clip);
  const Skeleton& s = clip.skeleton;
  for (const char* side : {"Left", "Right"}) {
    SCOPED_TRACE(side);
    const int hip = s.Find(std::string(side) + "UpLeg"), knee = s.Find(std::string(side) + "Leg");
    const int ankle = s.Find(std::string(side) + "Foot"), hand = s.Find(std::string(side) + "Hand");
    const int arm = s.Find(std::string(side) + "Arm");
    float flexion_min = 90, flexion_max = -90, knee_max = 0;
    double correlation = 0;
    for (int f = 0; f < clip.num_frames(); ++f) {
      const Eigen::Vector3f thigh = poses.position(f, knee) - poses.position(f, hip);
      const Eigen::Vector3f shin = poses.position(f, ankle) - poses.position(f, knee);
      const float flexion = std::atan2(thigh.z(), -thigh.y()) / kDegree;
      flexion_min = std::min(flexion_min, flexion);
      flexion_max = std::max(flexion_max, flexion);
      knee_max = std::max(knee_max, std::acos(thigh.normalized().dot(shin.normalized())) / kDegree);
      const float leg_forward = poses.pz(f, ankle) - poses.pz(f, hip);
      const float arm_forward = poses.pz(f, hand) - poses.pz(f, arm);
      correlation += leg_forward * arm_forward;
    }
    EXPECT_GT(flexion_max, 22);
    EXPECT_LT(flexion_max, 32);
    EXPECT_LT(flexion_min, -12);
    EXPECT_GT(flexion_min, -25);
    EXPECT_GT(knee_max, 45);
    EXPECT_LT(correlation, 0);
  }
}

TEST(SyntheticClipTest, EveryRigMovesTheSameWay) {
  const BvhClip reference_clip = testing::MakeWalkingClip({}, 30);
  const GlobalPoses reference = Poses(reference_clip);
  for (const RigCase& rig : RigCases()) {
    SCOPED_TRACE(rig.name);
    const BvhClip clip = testing::MakeWalkingClip(rig.options, 30);
    const GlobalPoses poses = Poses(clip);
    const float scale = static_cast<float>(rig.options.length_scale);
    float worst = 0;
    for (int j = 0; j < reference_clip.skeleton.num_joints(); ++j) {
      const int k = clip.skeleton.Find(reference_clip.skeleton.joint(j).name);
      ASSERT_GE(k, 0) << reference_clip.skeleton.joint(j).name;
      for (int f = 0; f < 30; ++f) {
        worst = std::max(worst, (poses.position(f, k) / scale - reference.position(f, j)).norm());
      }
    }
    EXPECT_LT(worst, 2e-3f) << "cm";
  }
}

TEST(SyntheticClipTest, FrameCountAndTime) {
  const BvhClip clip = testing::MakeWalkingClip({}, 7, 0.01);
  EXPECT_EQ(clip.num_frames(), 7);
  EXPECT_DOUBLE_EQ(clip.frame_time, 0.01);
  EXPECT_EQ(testing::MakeWalkingClip({}, 0).num_frames(), 0);
}

}  // namespace
}  // namespace mocap

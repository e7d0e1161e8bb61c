#include "motion/skeleton/local_motion.h"

#include <array>
#include <cmath>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "motion/skeleton/forward_kinematics.h"
#include "tests/support/rotation_checks.h"
#include "tests/support/synthetic_clip.h"

namespace mocap {
namespace {

using testing::AngleBetween;
using testing::kDegree;

ChannelType Rotation(char axis) {
  return axis == 'X' ? ChannelType::kXrotation : axis == 'Y' ? ChannelType::kYrotation : ChannelType::kZrotation;
}
int Axis(char axis) { return axis - 'X'; }

const std::array<std::string, 6> kOrders = {"XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX"};

// Root with 6 channels (positions then rotations in `order`), a child with 3 rotations in
// `order`, a grandchild with no channels.
Skeleton ThreeJointSkeleton(const std::string& order) {
  std::vector<ChannelType> rotations;
  for (char c : order) rotations.push_back(Rotation(c));
  std::vector<ChannelType> six = {ChannelType::kXposition, ChannelType::kYposition, ChannelType::kZposition};
  six.insert(six.end(), rotations.begin(), rotations.end());
  std::vector<Joint> joints;
  joints.push_back(Joint{.name = "Root", .parent = -1, .offset = Eigen::Vector3f(1, 2, 3), .channels = six});
  joints.push_back(Joint{.name = "Mid", .parent = 0, .offset = Eigen::Vector3f(0, 10, 0), .channels = rotations});
  joints.push_back(Joint{.name = "Tip", .parent = 1, .offset = Eigen::Vector3f(0, 5, 0)});
  return Skeleton(std::move(joints));
}

// The rotation R = R_order[0](a0) R_order[1](a1) R_order[2](a2), angles in degrees.
Eigen::Quaternionf Compose(const std::string& order, const float* degrees) {
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  for (int i = 0; i < 3; ++i) {
    q = q * Eigen::AngleAxisd(degrees[i] * kDegree, Eigen::Vector3d::Unit(Axis(order[i])));
  }
  return q.cast<float>();
}

class LocalMotionOrderTest : public ::testing::TestWithParam<std::string> {};

TEST_P(LocalMotionOrderTest, ChannelsRoundTripAwayFromGimbalLock) {
  const std::string& order = GetParam();
  const Skeleton skeleton = ThreeJointSkeleton(order);
  ASSERT_TRUE(skeleton.Validate().ok());
  std::mt19937 random(1234 + Axis(order[0]) * 7 + Axis(order[1]));
  std::uniform_real_distribution<float> outer(-179.0f, 179.0f), middle(-85.0f, 85.0f), position(-100.0f, 100.0f);
  constexpr int kFrames = 400;
  ChannelMatrix channels(kFrames, skeleton.num_channels());
  for (int f = 0; f < kFrames; ++f) {
    for (int c = 0; c < 3; ++c) channels(f, c) = position(random);
    for (int start : {3, 6}) {
      channels(f, start) = outer(random);
      channels(f, start + 1) = middle(random);
      channels(f, start + 2) = outer(random);
    }
  }
  const LocalMotion motion = MotionFromChannels(skeleton, channels, 1.0 / 60);
  ASSERT_EQ(motion.num_frames(), kFrames);
  ASSERT_EQ(motion.num_joints(), 3);
  EXPECT_DOUBLE_EQ(motion.frame_time, 1.0 / 60);
  const ChannelMatrix again = ChannelsFromMotion(skeleton, motion);
  ASSERT_EQ(again.rows(), kFrames);
  ASSERT_EQ(again.cols(), skeleton.num_channels());
  const LocalMotion motion_again = MotionFromChannels(skeleton, again, 1.0 / 60);
  double worst = 0, worst_composition = 0;
  for (int f = 0; f < kFrames; ++f) {
    for (int j = 0; j < 2; ++j) {
      // Intrinsic composition in channel order.
      const float* angles = &channels(f, j == 0 ? 3 : 6);
      worst_composition = std::max(worst_composition, AngleBetween(motion.rotation(f, j), Compose(order, angles)));
      EXPECT_NEAR(motion.rotation(f, j).norm(), 1.0f, 1e-5f);
      worst = std::max(worst, AngleBetween(motion.rotation(f, j), motion_again.rotation(f, j)));
    }
    EXPECT_NEAR(AngleBetween(motion.rotation(f, 2), Eigen::Quaternionf::Identity()), 0.0, 1e-7);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(again(f, c), channels(f, c), 1e-4f);
  }
  EXPECT_LT(worst_composition, 1e-5) << "radians";
  EXPECT_LT(worst, 2e-4) << "radians";
}

TEST_P(LocalMotionOrderTest, GimbalLockStillReproducesTheRotation) {
  const std::string& order = GetParam();
  const Skeleton skeleton = ThreeJointSkeleton(order);
  std::mt19937 random(99);
  std::uniform_real_distribution<float> outer(-170.0f, 170.0f);
  constexpr int kFrames = 40;
  ChannelMatrix channels = ChannelMatrix::Zero(kFrames, skeleton.num_channels());
  for (int f = 0; f < kFrames; ++f) {
    for (int start : {3, 6}) {
      channels(f, start) = outer(random);
      channels(f, start + 1) = f % 2 == 0 ? 90.0f : -90.0f;
      channels(f, start + 2) = outer(random);
    }
  }
  const LocalMotion motion = MotionFromChannels(skeleton, channels, 1.0 / 30);
  const LocalMotion motion_again = MotionFromChannels(skeleton, ChannelsFromMotion(skeleton, motion), 1.0 / 30);
  for (int f = 0; f < kFrames; ++f) {
    for (int j = 0; j < 2; ++j) {
      EXPECT_LT(AngleBetween(motion.rotation(f, j), motion_again.rotation(f, j)), 2e-3)
          << "frame " << f << " joint " << j << " angles " << channels.row(f);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(LocalMotionOrders, LocalMotionOrderTest, ::testing::ValuesIn(kOrders),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

TEST(LocalMotionTest, SingleRotationChannel) {
  std::vector<Joint> joints;
  joints.push_back(Joint{.name = "Root", .parent = -1, .channels = {ChannelType::kYrotation}});
  joints.push_back(
      Joint{.name = "Knee", .parent = 0, .offset = Eigen::Vector3f(1, 0, 0), .channels = {ChannelType::kXrotation}});
  const Skeleton skeleton(std::move(joints));
  ChannelMatrix channels(3, 2);
  channels << 30, 10, -120, 135, 179, -170;
  const LocalMotion motion = MotionFromChannels(skeleton, channels, 1.0 / 30);
  for (int f = 0; f < 3; ++f) {
    EXPECT_LT(AngleBetween(motion.rotation(f, 0),
                           Eigen::Quaternionf(Eigen::AngleAxisf(channels(f, 0) * kDegree, Eigen::Vector3f::UnitY()))),
              1e-6);
    EXPECT_LT(AngleBetween(motion.rotation(f, 1),
                           Eigen::Quaternionf(Eigen::AngleAxisf(channels(f, 1) * kDegree, Eigen::Vector3f::UnitX()))),
              1e-6);
  }
  const ChannelMatrix again = ChannelsFromMotion(skeleton, motion);
  for (int f = 0; f < 3; ++f) {
    for (int c = 0; c < 2; ++c) EXPECT_NEAR(again(f, c), channels(f, c), 1e-3f) << f << "," << c;
  }
}

// A joint with two rotation channels (X then Z) can hold any pair of angles; ChannelsFromMotion
// must pick the Euler branch whose missing third angle is zero, also when the second angle is
// beyond +-90 degrees.
TEST(LocalMotionTest, TwoRotationChannelsRoundTrip) {
  std::vector<Joint> joints;
  joints.push_back(Joint{.name = "Root", .parent = -1});
  joints.push_back(Joint{.name = "Elbow",
                         .parent = 0,
                         .offset = Eigen::Vector3f(1, 0, 0),
                         .channels = {ChannelType::kXrotation, ChannelType::kZrotation}});
  const Skeleton skeleton(std::move(joints));
  ChannelMatrix channels(4, 2);
  channels << 10, -20, 45, 60, -80, 170, 30, -120;
  const LocalMotion motion = MotionFromChannels(skeleton, channels, 1.0 / 30);
  for (int f = 0; f < 4; ++f) {
    const Eigen::Quaternionf elbow(Eigen::AngleAxisf(channels(f, 0) * kDegree, Eigen::Vector3f::UnitX()) *
                                   Eigen::AngleAxisf(channels(f, 1) * kDegree, Eigen::Vector3f::UnitZ()));
    EXPECT_LT(AngleBetween(motion.rotation(f, 1), elbow), 1e-6);
  }
  const LocalMotion again = MotionFromChannels(skeleton, ChannelsFromMotion(skeleton, motion), 1.0 / 30);
  for (int f = 0; f < 4; ++f) {
    EXPECT_LT(AngleBetween(again.rotation(f, 1), motion.rotation(f, 1)), 1e-4)
        << "frame " << f << ": X " << channels(f, 0) << ", Z " << channels(f, 1);
  }
}

TEST(LocalMotionTest, TranslationSemantics) {
  std::vector<Joint> joints;
  // Root: OFFSET + position channels.
  joints.push_back(Joint{.name = "Root",
                         .parent = -1,
                         .offset = Eigen::Vector3f(1, 2, 3),
                         .channels = {ChannelType::kZposition, ChannelType::kXposition, ChannelType::kYposition,
                                      ChannelType::kZrotation, ChannelType::kXrotation, ChannelType::kYrotation}});
  // Non-root with all three position channels: they replace the OFFSET.
  joints.push_back(Joint{.name = "Full",
                         .parent = 0,
                         .offset = Eigen::Vector3f(5, 6, 7),
                         .channels = {ChannelType::kXposition, ChannelType::kYposition, ChannelType::kZposition}});
  // Non-root with only Yposition: replaces that component only.
  joints.push_back(Joint{.name = "Partial",
                         .parent = 1,
                         .offset = Eigen::Vector3f(8, 9, 10),
                         .channels = {ChannelType::kYposition, ChannelType::kXrotation}});
  // No channels: OFFSET and identity.
  joints.push_back(Joint{.name = "Still", .parent = 2, .offset = Eigen::Vector3f(11, 12, 13)});
  const Skeleton skeleton(std::move(joints));
  ASSERT_EQ(skeleton.num_channels(), 11);
  ChannelMatrix channels(2, 11);
  channels << 30, 10, 20, 0, 0, 0, 100, 200, 300, 50, 0,  //
      -3, -1, -2, 0, 0, 0, -100, -200, -300, -50, 0;
  const LocalMotion motion = MotionFromChannels(skeleton, channels, 1.0 / 30);
  EXPECT_EQ(motion.translation(0, 0), Eigen::Vector3f(11, 22, 33));
  EXPECT_EQ(motion.translation(1, 0), Eigen::Vector3f(0, 0, 0));
  EXPECT_EQ(motion.translation(0, 1), Eigen::Vector3f(100, 200, 300));
  EXPECT_EQ(motion.translation(1, 1), Eigen::Vector3f(-100, -200, -300));
  EXPECT_EQ(motion.translation(0, 2), Eigen::Vector3f(8, 50, 10));
  EXPECT_EQ(motion.translation(1, 2), Eigen::Vector3f(8, -50, 10));
  for (int f = 0; f < 2; ++f) {
    EXPECT_EQ(motion.translation(f, 3), Eigen::Vector3f(11, 12, 13));
    EXPECT_EQ(motion.rotation(f, 3).coeffs(), Eigen::Quaternionf::Identity().coeffs());
    EXPECT_EQ(motion.rotation(f, 1).coeffs(), Eigen::Quaternionf::Identity().coeffs());
  }
  // And back.
  const ChannelMatrix again = ChannelsFromMotion(skeleton, motion);
  for (int f = 0; f < 2; ++f) {
    for (int c = 0; c < 11; ++c) EXPECT_NEAR(again(f, c), channels(f, c), 1e-5f) << f << "," << c;
  }
}

// Rotations, translations and frame time of `motion` at every frame, as arbitrary smooth data.
LocalMotion RandomSmoothMotion(int frames, int joints, double frame_time, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
  LocalMotion motion;
  motion.frame_time = frame_time;
  motion.Resize(frames, joints);
  for (int j = 0; j < joints; ++j) {
    const Eigen::Vector3f axis = Eigen::Vector3f(uniform(random), uniform(random), uniform(random)).normalized();
    const Eigen::Vector3f velocity(uniform(random), uniform(random), uniform(random));
    const Eigen::Vector3f start(10 * uniform(random), 10 * uniform(random), 10 * uniform(random));
    const float spin = 0.2f * uniform(random);
    for (int f = 0; f < frames; ++f) {
      motion.SetRotation(f, j, Eigen::Quaternionf(Eigen::AngleAxisf(0.3f + spin * f, axis)));
      motion.SetTranslation(f, j, start + velocity * static_cast<float>(f));
    }
  }
  return motion;
}

TEST(LocalMotionTest, Resample60To30PicksEveryOtherFrame) {
  for (int frames : {60, 61, 1}) {
    SCOPED_TRACE(frames);
    const LocalMotion motion = RandomSmoothMotion(frames, 4, 1.0 / 60, 7);
    const LocalMotion half = Resample(motion, 1.0 / 30);
    EXPECT_DOUBLE_EQ(half.frame_time, 1.0 / 30);
    ASSERT_EQ(half.num_frames(), (frames - 1) / 2 + 1);
    ASSERT_EQ(half.num_joints(), 4);
    for (int k = 0; k < half.num_frames(); ++k) {
      for (int j = 0; j < 4; ++j) {
        EXPECT_EQ(half.rotation(k, j).coeffs(), motion.rotation(2 * k, j).coeffs()) << k << "," << j;
        EXPECT_EQ(half.translation(k, j), motion.translation(2 * k, j)) << k << "," << j;
      }
    }
  }
}

TEST(LocalMotionTest, ResampleInterpolatesHalfwayBetweenFrames) {
  LocalMotion motion = RandomSmoothMotion(31, 3, 1.0 / 30, 11);
  // Stored signs must not matter: flip every other quaternion of joint 1.
  for (int f = 1; f < motion.num_frames(); f += 2) {
    motion.SetRotation(f, 1, Eigen::Quaternionf(-motion.rotation(f, 1).coeffs()));
  }
  const LocalMotion doubled = Resample(motion, 1.0 / 60);
  ASSERT_EQ(doubled.num_frames(), 61);
  for (int k = 0; k < doubled.num_frames(); ++k) {
    const int f = k / 2;
    for (int j = 0; j < 3; ++j) {
      if (k % 2 == 0) {
        EXPECT_LT(AngleBetween(doubled.rotation(k, j), motion.rotation(f, j)), 1e-6);
        EXPECT_TRUE(doubled.translation(k, j).isApprox(motion.translation(f, j), 1e-6f));
        continue;
      }
      // Halfway along the shortest arc: the normalised sum of the two (sign-aligned) quaternions.
      Eigen::Vector4f a = motion.rotation(f, j).coeffs(), b = motion.rotation(f + 1, j).coeffs();
      if (a.dot(b) < 0) b = -b;
      const Eigen::Quaternionf expected(Eigen::Vector4f((a + b).normalized()));
      EXPECT_LT(AngleBetween(doubled.rotation(k, j), expected), 1e-5) << k << "," << j;
      EXPECT_NEAR(doubled.rotation(k, j).norm(), 1.0f, 1e-5f);
      const Eigen::Vector3f middle = 0.5f * (motion.translation(f, j) + motion.translation(f + 1, j));
      EXPECT_LT((doubled.translation(k, j) - middle).norm(), 1e-4f) << k << "," << j;
    }
  }
}

TEST(LocalMotionTest, ResampleToAnUnrelatedRate) {
  const LocalMotion motion = RandomSmoothMotion(60, 2, 1.0 / 60, 3);
  const LocalMotion out = Resample(motion, 1.0 / 25);
  // Duration 59/60 s holds times 0, 0.04, ..., 0.96: 25 frames.
  ASSERT_EQ(out.num_frames(), 25);
  for (int k : {0, 1, 7, 24}) {
    const double position = k * 60.0 / 25.0;
    const int f = static_cast<int>(std::floor(position));
    const float u = static_cast<float>(position - f);
    for (int j = 0; j < 2; ++j) {
      const Eigen::Quaternionf expected = motion.rotation(f, j).slerp(u, motion.rotation(std::min(f + 1, 59), j));
      EXPECT_LT(AngleBetween(out.rotation(k, j), expected), 1e-5) << k;
      const Eigen::Vector3f t = (1 - u) * motion.translation(f, j) + u * motion.translation(std::min(f + 1, 59), j);
      EXPECT_LT((out.translation(k, j) - t).norm(), 1e-4f) << k;
    }
  }
}

// An empty motion resamples to an empty motion whatever the rates. Run in a child process: the
// failure mode is a negative frame count, which aborts inside Eigen in debug builds.
TEST(LocalMotionTest, ResampleOfAnEmptyMotionIsEmpty) {
  for (double target : {1.0 / 30, 1.0 / 120}) {
    EXPECT_EXIT(
        {
          LocalMotion empty;
          empty.frame_time = 1.0 / 60;
          empty.Resize(0, 3);
          const LocalMotion out = Resample(empty, target);
          std::exit(out.num_frames() == 0 && out.num_joints() == 3 ? 0 : 1);
        },
        ::testing::ExitedWithCode(0), "")
        << "target frame time " << target;
  }
}

// Positions of every joint at every frame.
std::vector<Eigen::Vector3f> AllPositions(const GlobalPoses& poses) {
  std::vector<Eigen::Vector3f> out;
  for (int f = 0; f < poses.num_frames(); ++f) {
    for (int j = 0; j < poses.num_joints(); ++j) out.push_back(poses.position(f, j));
  }
  return out;
}

TEST(LocalMotionTest, RotateWorldRotatesEveryJoint) {
  const BvhClip clip = testing::MakeWalkingClip({.fingers_and_toes = true}, 20);
  const LocalMotion motion = MotionFromChannels(clip.skeleton, clip.channels, clip.frame_time);
  const Eigen::Quaternionf rotation(Eigen::AngleAxisf(0.7f, Eigen::Vector3f(1, 2, -0.5f).normalized()));
  LocalMotion rotated = motion;
  RotateWorld(rotated, rotation);
  EXPECT_DOUBLE_EQ(rotated.frame_time, motion.frame_time);
  const GlobalPoses before = ForwardKinematics(clip.skeleton, motion);
  const GlobalPoses after = ForwardKinematics(clip.skeleton, rotated);
  for (int f = 0; f < before.num_frames(); ++f) {
    for (int j = 0; j < before.num_joints(); ++j) {
      EXPECT_LT((after.position(f, j) - rotation * before.position(f, j)).norm(), 1e-3f) << f << "," << j;
      EXPECT_LT(AngleBetween(after.rotation(f, j), rotation * before.rotation(f, j)), 1e-5) << f << "," << j;
    }
  }
  // Only the root changes locally.
  for (int j = 1; j < motion.num_joints(); ++j) {
    EXPECT_TRUE((rotated.qw.col(j) == motion.qw.col(j)).all());
    EXPECT_TRUE((rotated.tx.col(j) == motion.tx.col(j)).all());
  }
}

TEST(LocalMotionTest, RotateWorldTurnsZUpIntoYUp) {
  // The z_up rig's RL_BoneRoot already turns the world Y-up: removing that root rotation and
  // applying it with RotateWorld instead gives the same poses.
  const BvhClip clip = testing::MakeWalkingClip({.z_up = true}, 10);
  LocalMotion motion = MotionFromChannels(clip.skeleton, clip.channels, clip.frame_time);
  const GlobalPoses expected = ForwardKinematics(clip.skeleton, motion);
  const Eigen::Quaternionf to_y_up(Eigen::AngleAxisf(-M_PI / 2, Eigen::Vector3f::UnitX()));
  ASSERT_LT(AngleBetween(motion.rotation(0, 0), to_y_up), 1e-6);
  for (int f = 0; f < motion.num_frames(); ++f) {
    // The root's translation is in world axes already: express it in the Z-up frame too.
    motion.SetRotation(f, 0, Eigen::Quaternionf::Identity());
    motion.SetTranslation(f, 0, to_y_up.conjugate() * motion.translation(f, 0));
  }
  RotateWorld(motion, to_y_up);
  const GlobalPoses actual = ForwardKinematics(clip.skeleton, motion);
  for (int f = 0; f < motion.num_frames(); ++f) {
    for (int j = 0; j < motion.num_joints(); ++j) {
      EXPECT_LT((actual.position(f, j) - expected.position(f, j)).norm(), 1e-3f);
    }
  }
}

TEST(LocalMotionTest, ScaleTranslationsScalesPositionsNotRotations) {
  const BvhClip clip = testing::MakeWalkingClip({.twist_bones = true}, 15);
  const LocalMotion motion = MotionFromChannels(clip.skeleton, clip.channels, clip.frame_time);
  LocalMotion metres = motion;
  ScaleTranslations(metres, 0.01f);
  const std::vector<Eigen::Vector3f> cm = AllPositions(ForwardKinematics(clip.skeleton, motion));
  const std::vector<Eigen::Vector3f> m = AllPositions(ForwardKinematics(clip.skeleton, metres));
  ASSERT_EQ(cm.size(), m.size());
  for (size_t i = 0; i < cm.size(); ++i) EXPECT_LT((m[i] - 0.01f * cm[i]).norm(), 1e-5f) << i;
  EXPECT_TRUE((metres.qx == motion.qx).all());
  EXPECT_TRUE((metres.qw == motion.qw).all());
  // Same as building the rig in metres.
  testing::SyntheticRigOptions options{.twist_bones = true, .length_scale = 0.01};
  const BvhClip clip_m = testing::MakeWalkingClip(options, 15);
  const std::vector<Eigen::Vector3f> built = AllPositions(
      ForwardKinematics(clip_m.skeleton, MotionFromChannels(clip_m.skeleton, clip_m.channels, clip_m.frame_time)));
  for (size_t i = 0; i < built.size(); ++i) EXPECT_LT((built[i] - m[i]).norm(), 1e-5f) << i;
}

// The synthetic rigs survive MotionFromChannels -> ChannelsFromMotion -> MotionFromChannels.
TEST(LocalMotionTest, SyntheticClipsRoundTripThroughChannels) {
  std::vector<testing::SyntheticRigOptions> rigs;
  for (const std::string& order : kOrders) {
    rigs.push_back({.rotation_order = order});
    rigs.push_back({.extra_root = true,
                    .z_up = true,
                    .fingers_and_toes = true,
                    .twist_bones = true,
                    .position_channels_everywhere = true,
                    .rotation_order = order});
    rigs.push_back({.z_up = true, .rotation_order = order});
  }
  for (const testing::SyntheticRigOptions& rig : rigs) {
    SCOPED_TRACE(rig.rotation_order + (rig.z_up ? " z_up" : "") + (rig.extra_root ? " everything" : ""));
    const BvhClip clip = testing::MakeWalkingClip(rig, 30);
    const LocalMotion motion = MotionFromChannels(clip.skeleton, clip.channels, clip.frame_time);
    const ChannelMatrix channels = ChannelsFromMotion(clip.skeleton, motion);
    const LocalMotion again = MotionFromChannels(clip.skeleton, channels, clip.frame_time);
    double worst = 0;
    for (int f = 0; f < motion.num_frames(); ++f) {
      for (int j = 0; j < motion.num_joints(); ++j) {
        worst = std::max(worst, AngleBetween(motion.rotation(f, j), again.rotation(f, j)));
        EXPECT_LT((motion.translation(f, j) - again.translation(f, j)).norm(), 1e-3f);
      }
    }
    EXPECT_LT(worst, 2e-4) << "radians";
  }
}

}  // namespace
}  // namespace mocap

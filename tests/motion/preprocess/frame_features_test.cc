#include "motion/preprocess/frame_features.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "motion/preprocess/clip_preprocessor.h"
#include "motion/skeleton/forward_kinematics.h"
#include "motion/skeleton/local_motion.h"
#include "tests/support/rotation_checks.h"
#include "tests/support/synthetic_clip.h"

namespace mocap {
namespace {

using testing::AngleBetween;
using testing::kDegree;
using testing::kPi;

using testing::MakeWalkingClip;
using testing::SyntheticRigOptions;

Eigen::Vector3f Vec(const float v[3]) { return Eigen::Vector3f(v[0], v[1], v[2]); }

// a - b wrapped into (-pi, pi].
float AngleDifference(float a, float b) { return std::remainder(a - b, 2 * kPi); }

Eigen::Matrix3f YRotation(float heading) {
  return Eigen::AngleAxisf(heading, Eigen::Vector3f::UnitY()).toRotationMatrix();
}

// ---------------------------------------------------------------------------------------------
// WristReferenceFrame.

void ExpectOrthonormalYUp(const ReferenceFrame& frame) {
  EXPECT_TRUE((frame.rotation.transpose() * frame.rotation).isApprox(Eigen::Matrix3f::Identity(), 1e-5f));
  EXPECT_NEAR(frame.rotation.determinant(), 1.0f, 1e-5f);
  EXPECT_LT((frame.rotation.col(1) - Eigen::Vector3f::UnitY()).norm(), 1e-6f);
  EXPECT_LT((frame.rotation.col(0).cross(frame.rotation.col(1)) - frame.rotation.col(2)).norm(), 1e-6f);
}

TEST(FrameFeaturesTest, WristReferenceFrameAxesAndOrigin) {
  const Eigen::Vector3f left(1.0f, 1.2f, 2.0f), right(-1.0f, 0.9f, 3.0f);
  float heading = 123.0f;
  const ReferenceFrame frame = WristReferenceFrame(left, right, /*fallback_heading=*/2.0f, &heading);
  ExpectOrthonormalYUp(frame);
  // Origin on the ground below the midpoint of the wrists.
  EXPECT_LT((frame.origin - Eigen::Vector3f(0.0f, 0.0f, 2.5f)).norm(), 1e-6f);
  // x axis: ground projection of right -> left.
  const Eigen::Vector3f x_expected = Eigen::Vector3f(2.0f, 0.0f, -1.0f).normalized();
  EXPECT_LT((frame.rotation.col(0) - x_expected).norm(), 1e-6f);
  // z = x cross y: the wrists face +Z-ish here.
  EXPECT_LT((frame.rotation.col(2) - Eigen::Vector3f(1.0f, 0.0f, 2.0f).normalized()).norm(), 1e-6f);
  // The heading: x axis = (cos h, 0, -sin h).
  EXPECT_NEAR(std::cos(heading), x_expected.x(), 1e-6f);
  EXPECT_NEAR(-std::sin(heading), x_expected.z(), 1e-6f);
  EXPECT_TRUE(frame.rotation.isApprox(YRotation(heading), 1e-6f));
  // Local coordinates: wrists on the local x axis, symmetric about the origin.
  const Eigen::Vector3f l = frame.ToLocal(left), r = frame.ToLocal(right);
  EXPECT_NEAR(l.x(), std::sqrt(5.0f) / 2, 1e-5f);
  EXPECT_NEAR(r.x(), -std::sqrt(5.0f) / 2, 1e-5f);
  EXPECT_NEAR(l.y(), 1.2f, 1e-6f);
  EXPECT_NEAR(r.y(), 0.9f, 1e-6f);
  EXPECT_NEAR(l.z(), 0.0f, 1e-6f);
  EXPECT_NEAR(r.z(), 0.0f, 1e-6f);
  // Directions ignore the origin.
  EXPECT_LT((frame.DirectionToLocal(x_expected) - Eigen::Vector3f::UnitX()).norm(), 1e-6f);
  // No heading pointer is fine.
  const ReferenceFrame again = WristReferenceFrame(left, right, 0.0f, nullptr);
  EXPECT_TRUE(again.rotation.isApprox(frame.rotation));
}

TEST(FrameFeaturesTest, WristReferenceFrameOfAFacingCharacter) {
  // A character facing +Z has its left wrist at +X: the reference frame is the world's.
  float heading = 1.0f;
  const ReferenceFrame frame =
      WristReferenceFrame(Eigen::Vector3f(0.3f, 1.0f, 5.0f), Eigen::Vector3f(-0.3f, 1.0f, 5.0f), 0.0f, &heading);
  EXPECT_NEAR(heading, 0.0f, 1e-6f);
  EXPECT_TRUE(frame.rotation.isApprox(Eigen::Matrix3f::Identity(), 1e-6f));
  // Facing -X: left (= up x forward) is +Z.
  const ReferenceFrame turned =
      WristReferenceFrame(Eigen::Vector3f(0.0f, 1.0f, 0.3f), Eigen::Vector3f(0.0f, 1.0f, -0.3f), 0.0f, &heading);
  EXPECT_LT((turned.rotation.col(2) - Eigen::Vector3f(-1, 0, 0)).norm(), 1e-6f);
  EXPECT_NEAR(AngleDifference(heading, -kPi / 2), 0.0f, 1e-6f);
}

TEST(FrameFeaturesTest, WristReferenceFrameFallsBackWhenWristsAreVerticallyAligned) {
  for (float fallback : {0.0f, 0.7f, -2.9f}) {
    for (const Eigen::Vector3f& offset :
         {Eigen::Vector3f(0, 0.6f, 0), Eigen::Vector3f(0.0005f, -0.4f, 0.0003f)}) {  // < 1 mm apart on the ground
      const Eigen::Vector3f left(0.3f, 1.5f, 0.2f);
      float heading = 100.0f;
      const ReferenceFrame frame = WristReferenceFrame(left, left + offset, fallback, &heading);
      EXPECT_EQ(heading, fallback);
      ExpectOrthonormalYUp(frame);
      EXPECT_TRUE(frame.rotation.isApprox(YRotation(fallback), 1e-6f));
      const Eigen::Vector3f midpoint = left + 0.5f * offset;
      EXPECT_LT((frame.origin - Eigen::Vector3f(midpoint.x(), 0, midpoint.z())).norm(), 1e-6f);
    }
  }
  // 2 mm apart: the wrists decide.
  float heading = 100.0f;
  WristReferenceFrame(Eigen::Vector3f(0.002f, 1, 0), Eigen::Vector3f(0, 1.2f, 0), 0.7f, &heading);
  EXPECT_NEAR(heading, 0.0f, 1e-5f);
}

// ---------------------------------------------------------------------------------------------
// ComputeFrameFeatures on hand-made poses.

// Joints: 0 pelvis, 1 left wrist, 2 right wrist, 3 left ankle, 4 right ankle.
constexpr BodyLandmarks kHandLandmarks = {
    .pelvis = 0, .head = -1, .left_wrist = 1, .right_wrist = 2, .left_ankle = 3, .right_ankle = 4};

GlobalPoses HandPoses(const std::vector<std::vector<Eigen::Vector3f>>& positions,
                      const std::vector<Eigen::Quaternionf>& pelvis_rotations) {
  const int frames = static_cast<int>(positions.size());
  const int joints = static_cast<int>(positions[0].size());
  GlobalPoses poses;
  for (Eigen::ArrayXXf* a : {&poses.px, &poses.py, &poses.pz, &poses.qx, &poses.qy, &poses.qz}) {
    a->setZero(frames, joints);
  }
  poses.qw.setOnes(frames, joints);
  for (int f = 0; f < frames; ++f) {
    for (int j = 0; j < joints; ++j) {
      poses.px(f, j) = positions[f][j].x();
      poses.py(f, j) = positions[f][j].y();
      poses.pz(f, j) = positions[f][j].z();
    }
    poses.qw(f, 0) = pelvis_rotations[f].w();
    poses.qx(f, 0) = pelvis_rotations[f].x();
    poses.qy(f, 0) = pelvis_rotations[f].y();
    poses.qz(f, 0) = pelvis_rotations[f].z();
  }
  return poses;
}

TEST(FrameFeaturesTest, HandMadePosesHeadingFallbackAndPelvis) {
  const Eigen::Vector3f pelvis(0.1f, 0.9f, 0.2f);
  const Eigen::Vector3f ankle_l(0.1f, 0.08f, 0.0f), ankle_r(-0.1f, 0.08f, 0.3f);
  const Eigen::Quaternionf tilt30(Eigen::AngleAxisf(30 * kDegree, Eigen::Vector3f::UnitX()));
  const Eigen::Quaternionf yaw(Eigen::AngleAxisf(0.4f, Eigen::Vector3f::UnitY()));
  const GlobalPoses poses = HandPoses(
      {
          // 0: wrists vertically aligned: takes the first usable heading (frame 1's).
          {pelvis, {0.2f, 1.0f, 0.3f}, {0.2f, 1.4f, 0.3f}, ankle_l, ankle_r},
          // 1: left - right = (1, 0, -1): heading pi/4.
          {pelvis, {0.5f, 1.0f, 0.0f}, {-0.5f, 1.0f, 1.0f}, ankle_l, ankle_r},
          // 2: aligned within 1 mm: keeps the previous frame's heading.
          {pelvis, {0.0f, 1.0f, 0.0f}, {0.0f, 0.8f, 0.0005f}, ankle_l, ankle_r},
          // 3: left - right = (0, 0, -2): heading pi/2.
          {pelvis + Eigen::Vector3f(0, 0.1f, 0), {0.0f, 1.0f, -1.0f}, {0.0f, 1.0f, 1.0f}, ankle_l, ankle_r},
      },
      {Eigen::Quaternionf::Identity(), tilt30, yaw, yaw * tilt30});
  const double frame_time = 0.1;
  const std::vector<FrameFeatures> features =
      ComputeFrameFeatures(poses, kHandLandmarks, Eigen::Vector3f::UnitY(), frame_time);
  ASSERT_EQ(features.size(), 4u);
  EXPECT_NEAR(features[0].ref_heading, kPi / 4, 1e-6f);
  EXPECT_NEAR(features[1].ref_heading, kPi / 4, 1e-6f);
  EXPECT_NEAR(features[2].ref_heading, kPi / 4, 1e-6f);
  EXPECT_NEAR(features[3].ref_heading, kPi / 2, 1e-6f);
  EXPECT_NEAR(features[0].ref_origin_x, 0.2f, 1e-6f);
  EXPECT_NEAR(features[0].ref_origin_z, 0.3f, 1e-6f);
  EXPECT_NEAR(features[1].ref_origin_x, 0.0f, 1e-6f);
  EXPECT_NEAR(features[1].ref_origin_z, 0.5f, 1e-6f);

  // Frame 1 by hand: x axis (1, 0, -1)/sqrt2, z axis (1, 0, 1)/sqrt2, origin (0, 0, 0.5).
  const float h = std::sqrt(0.5f);
  EXPECT_LT((Vec(features[1].wrist_position[0]) - Eigen::Vector3f(h, 1.0f, 0.0f)).norm(), 1e-6f);
  EXPECT_LT((Vec(features[1].wrist_position[1]) - Eigen::Vector3f(-h, 1.0f, 0.0f)).norm(), 1e-6f);
  // Left ankle (0.1, 0.08, 0) - origin = (0.1, 0.08, -0.5).
  EXPECT_LT((Vec(features[1].ankle_position[0]) - Eigen::Vector3f(0.6f * h, 0.08f, -0.4f * h)).norm(), 1e-6f);
  // Left wrist velocity at frame 1: ((0.5, 1, 0) - (0.2, 1, 0.3)) / 0.1 = (3, 0, -3) -> (3 sqrt2, 0, 0).
  EXPECT_LT((Vec(features[1].wrist_velocity[0]) - Eigen::Vector3f(3.0f / h, 0.0f, 0.0f)).norm(), 1e-4f);
  // Frame 0 takes the forward difference (the same one), in frame 0's reference (also pi/4).
  EXPECT_LT((Vec(features[0].wrist_velocity[0]) - Eigen::Vector3f(3.0f / h, 0.0f, 0.0f)).norm(), 1e-4f);
  // Still ankles.
  EXPECT_LT(Vec(features[2].ankle_velocity[1]).norm(), 1e-6f);

  // Pelvis: height, tilt, position and rotation in the reference frame.
  EXPECT_NEAR(features[0].pelvis_height, 0.9f, 1e-6f);
  EXPECT_NEAR(features[3].pelvis_height, 1.0f, 1e-6f);
  EXPECT_NEAR(features[0].pelvis_tilt, 0.0f, 1e-3f);
  EXPECT_NEAR(features[1].pelvis_tilt, 30 * kDegree, 1e-5f);
  EXPECT_NEAR(features[2].pelvis_tilt, 0.0f, 1e-3f);  // yaw is not tilt
  EXPECT_NEAR(features[3].pelvis_tilt, 30 * kDegree, 1e-5f);
  EXPECT_LT(
      (Vec(features[1].pelvis_position) - Eigen::Vector3f(0.1f * h - (-0.3f) * h, 0.9f, 0.1f * h + -0.3f * h)).norm(),
      1e-6f);
  for (int f = 0; f < 4; ++f) {
    const float* q = features[f].pelvis_rotation;
    EXPECT_GE(q[0], 0.0f);
    EXPECT_NEAR(Eigen::Vector4f(q[0], q[1], q[2], q[3]).norm(), 1.0f, 1e-5f);
    const Eigen::Quaternionf world(poses.qw(f, 0), poses.qx(f, 0), poses.qy(f, 0), poses.qz(f, 0));
    const Eigen::Quaternionf expected =
        Eigen::Quaternionf(Eigen::AngleAxisf(-features[f].ref_heading, Eigen::Vector3f::UnitY())) * world;
    EXPECT_LT(AngleBetween(Eigen::Quaternionf(q[0], q[1], q[2], q[3]), expected), 1e-5) << f;
  }
}

TEST(FrameFeaturesTest, PelvisUpLocalDecidesTheTilt) {
  // A pelvis whose local "up" is +Z (a Z-up rig) standing upright: rotated -90 deg about X.
  const Eigen::Quaternionf upright(Eigen::AngleAxisf(-kPi / 2, Eigen::Vector3f::UnitX()));
  const std::vector<Eigen::Vector3f> frame = {
      {0, 0.9f, 0}, {0.3f, 1, 0}, {-0.3f, 1, 0}, {0.1f, 0.1f, 0}, {-0.1f, 0.1f, 0}};
  const GlobalPoses poses = HandPoses({frame}, {upright});
  EXPECT_NEAR(ComputeFrameFeatures(poses, kHandLandmarks, Eigen::Vector3f::UnitZ(), 0.1)[0].pelvis_tilt, 0.0f, 1e-3f);
  EXPECT_NEAR(ComputeFrameFeatures(poses, kHandLandmarks, Eigen::Vector3f::UnitY(), 0.1)[0].pelvis_tilt, kPi / 2,
              1e-5f);
  // One frame: no velocities.
  const FrameFeatures single = ComputeFrameFeatures(poses, kHandLandmarks, Eigen::Vector3f::UnitZ(), 0.1)[0];
  EXPECT_EQ(Vec(single.wrist_velocity[0]), Eigen::Vector3f::Zero());
  EXPECT_EQ(Vec(single.ankle_velocity[1]), Eigen::Vector3f::Zero());
}

// ---------------------------------------------------------------------------------------------
// ComputeFrameFeatures on the synthetic walk.

struct PreparedWalk {
  BvhClip clip;
  RigModel rig;
  PreparedClip prepared;
};

PreparedWalk PrepareWalk(const SyntheticRigOptions& options, int frames = 60) {
  PreparedWalk walk;
  walk.clip = MakeWalkingClip(options, frames);
  absl::StatusOr<RigModel> rig = BuildRigModel(walk.clip, {});
  EXPECT_TRUE(rig.ok()) << rig.status();
  if (!rig.ok()) return walk;
  walk.rig = *std::move(rig);
  absl::StatusOr<PreparedClip> prepared = PrepareClip(walk.clip, walk.rig, {});
  EXPECT_TRUE(prepared.ok()) << prepared.status();
  if (prepared.ok()) walk.prepared = *std::move(prepared);
  return walk;
}

class FrameFeaturesWalkTest : public ::testing::TestWithParam<int> {
 protected:
  SyntheticRigOptions Options() const {
    SyntheticRigOptions options;
    options.extra_root = (GetParam() & 1) != 0;
    options.z_up = (GetParam() & 2) != 0;
    options.fingers_and_toes = (GetParam() & 4) != 0;
    options.twist_bones = (GetParam() & 8) != 0;
    return options;
  }
};

TEST_P(FrameFeaturesWalkTest, WalkingCharacterFacingPlusZ) {
  const PreparedWalk walk = PrepareWalk(Options());
  const std::vector<FrameFeatures>& features = walk.prepared.features;
  ASSERT_EQ(static_cast<int>(features.size()), 60);
  // The Hips of the source clip by independent forward kinematics, in cm.
  const LocalMotion source = MotionFromChannels(walk.clip.skeleton, walk.clip.channels, walk.clip.frame_time);
  const GlobalPoses source_poses = ForwardKinematics(walk.clip.skeleton, source);
  const int hips = walk.clip.skeleton.Find("Hips");
  ASSERT_GE(hips, 0);

  int planted = 0;
  double mean_velocity_x = 0, mean_velocity_z = 0, mean_heading = 0, mean_height = 0;
  for (int f = 0; f < 60; ++f) {
    SCOPED_TRACE(f);
    const FrameFeatures& ff = features[f];
    EXPECT_GT(ff.wrist_position[0][0], 0.1f);   // left wrist on local +x
    EXPECT_LT(ff.wrist_position[1][0], -0.1f);  // right wrist on local -x
    // Arms hang: wrists between knee and hip height.
    EXPECT_GT(ff.wrist_position[0][1], 0.5f);
    EXPECT_LT(ff.wrist_position[0][1], 1.0f);
    // The arms swing opposite to each other, so the heading wobbles about 0 but the frame
    // always faces +Z.
    EXPECT_LT(std::abs(ff.ref_heading), 35 * kDegree);
    mean_heading += ff.ref_heading / 60;
    // Planted feet (world velocity ~0): ankle at kSyntheticAnkleHeight.
    for (int side = 0; side < 2; ++side) {
      if (Vec(ff.ankle_velocity[side]).norm() < 0.01f) {
        ++planted;
        EXPECT_NEAR(ff.ankle_position[side][1], testing::kSyntheticAnkleHeight / 100, 1e-3) << "side " << side;
      }
      EXPECT_GT(ff.ankle_position[side][1], testing::kSyntheticAnkleHeight / 100 - 1e-3);
    }
    // Pelvis height = the Hips' height; pelvis position's local y is the same height.
    EXPECT_NEAR(ff.pelvis_height, source_poses.py(f, hips) / 100, 1e-4f);
    EXPECT_NEAR(ff.pelvis_position[1], ff.pelvis_height, 1e-5f);
    mean_height += ff.pelvis_height / 60;
    // Upright walk: the pelvis only yaws.
    EXPECT_LT(ff.pelvis_tilt, 2 * kDegree);
    for (int side = 0; side < 2; ++side) {
      mean_velocity_x += 0.5 * ff.wrist_velocity[side][0] / 60;
      mean_velocity_z += 0.5 * ff.wrist_velocity[side][2] / 60;
    }
  }
  // Each foot stands for about half of the clip.
  EXPECT_GT(planted, 40);
  EXPECT_LT(std::abs(mean_heading), 5 * kDegree);
  EXPECT_NEAR(mean_height, 0.92, 0.03);
  // The wrists travel with the body: ~1.2 m/s along local +z on average.
  EXPECT_NEAR(mean_velocity_z, testing::kSyntheticWalkSpeed / 100, 0.15);
  EXPECT_NEAR(mean_velocity_x, 0.0, 0.1);
}

INSTANTIATE_TEST_SUITE_P(Rigs, FrameFeaturesWalkTest, ::testing::Values(0, 1, 2, 4 | 8, 15));

TEST(FrameFeaturesTest, PlayedBackwardsIsWhatTheReversedClipMeasures) {
  // A synthetic walk and the same channels in reverse order, prepared as any clip is.
  const PreparedWalk walk = PrepareWalk({}, 60);
  PreparedWalk reversed = walk;
  reversed.clip.channels = walk.clip.channels.colwise().reverse();
  absl::StatusOr<PreparedClip> measured = PrepareClip(reversed.clip, walk.rig, {});
  ASSERT_TRUE(measured.ok()) << measured.status();
  const std::vector<FrameFeatures> played = PlayedBackwards(walk.prepared.features);
  ASSERT_EQ(played.size(), measured->features.size());
  for (size_t f = 0; f < played.size(); ++f) {
    SCOPED_TRACE(f);
    const FrameFeatures& a = played[f];
    const FrameFeatures& b = measured->features[f];
    EXPECT_NEAR(AngleDifference(a.ref_heading, b.ref_heading), 0.0f, 1e-4f);
    EXPECT_NEAR(a.pelvis_height, b.pelvis_height, 1e-4f);
    for (int side = 0; side < 2; ++side) {
      EXPECT_LT((Vec(a.wrist_position[side]) - Vec(b.wrist_position[side])).norm(), 1e-4f);
      EXPECT_LT((Vec(a.ankle_position[side]) - Vec(b.ankle_position[side])).norm(), 1e-4f);
      EXPECT_LT((Vec(a.wrist_velocity[side]) - Vec(b.wrist_velocity[side])).norm(), 2e-3f);
      EXPECT_LT((Vec(a.ankle_velocity[side]) - Vec(b.ankle_velocity[side])).norm(), 2e-3f);
    }
  }
}

TEST(FrameFeaturesTest, VelocityIsRotatedFiniteDifferenceOfWorldPositions) {
  const PreparedWalk walk = PrepareWalk({});
  const PreparedClip& prepared = walk.prepared;
  ASSERT_EQ(prepared.num_frames(), 60);
  const GlobalPoses poses = ForwardKinematics(prepared.skeleton, prepared.motion);
  const BodyLandmarks& l = walk.rig.topology.landmarks;
  const float rate = static_cast<float>(1.0 / prepared.motion.frame_time);
  ASSERT_NEAR(rate, 30.0f, 1e-4f);
  for (int f : {0, 17, 59}) {
    SCOPED_TRACE(f);
    const int a = f == 0 ? 0 : f - 1, b = f == 0 ? 1 : f;
    const Eigen::Matrix3f to_local = YRotation(prepared.features[f].ref_heading).transpose();
    auto local_velocity = [&](int joint) -> Eigen::Vector3f {
      return to_local * ((poses.position(b, joint) - poses.position(a, joint)) * rate);
    };
    EXPECT_LT((Vec(prepared.features[f].wrist_velocity[0]) - local_velocity(l.left_wrist)).norm(), 1e-4f);
    EXPECT_LT((Vec(prepared.features[f].wrist_velocity[1]) - local_velocity(l.right_wrist)).norm(), 1e-4f);
    EXPECT_LT((Vec(prepared.features[f].ankle_velocity[0]) - local_velocity(l.left_ankle)).norm(), 1e-4f);
    EXPECT_LT((Vec(prepared.features[f].ankle_velocity[1]) - local_velocity(l.right_ankle)).norm(), 1e-4f);
    // And the positions.
    const Eigen::Vector3f origin(prepared.features[f].ref_origin_x, 0, prepared.features[f].ref_origin_z);
    EXPECT_LT(
        (Vec(prepared.features[f].wrist_position[0]) - to_local * (poses.position(f, l.left_wrist) - origin)).norm(),
        1e-5f);
    EXPECT_LT(
        (Vec(prepared.features[f].ankle_position[1]) - to_local * (poses.position(f, l.right_ankle) - origin)).norm(),
        1e-5f);
  }
  // A swinging foot moves: the features are not all zero.
  float fastest = 0;
  for (const FrameFeatures& ff : prepared.features) fastest = std::max(fastest, Vec(ff.ankle_velocity[0]).norm());
  EXPECT_GT(fastest, 2.0f);
}

// The point of A1: the same clip anywhere on the ground, facing anywhere, has the same local
// features; only the reference frame's placement differs.
TEST(FrameFeaturesTest, InvariantUnderRotationAboutVerticalAndGroundTranslation) {
  const PreparedWalk walk = PrepareWalk({});
  const PreparedClip& prepared = walk.prepared;
  ASSERT_EQ(prepared.num_frames(), 60);
  const BodyLandmarks& landmarks = walk.rig.topology.landmarks;
  const std::vector<FrameFeatures> base =
      ComputeFrameFeatures(ForwardKinematics(prepared.skeleton, prepared.motion), landmarks, walk.rig.pelvis_up_local,
                           prepared.motion.frame_time);
  // PrepareClip's own features are these.
  ASSERT_EQ(base.size(), prepared.features.size());
  for (size_t f = 0; f < base.size(); ++f) {
    EXPECT_EQ(0, std::memcmp(&base[f], &prepared.features[f], sizeof(FrameFeatures))) << f;
  }
  for (const float yaw : {1.3f, -2.4f, 3.1f}) {
    SCOPED_TRACE(yaw);
    const Eigen::Quaternionf rotation(Eigen::AngleAxisf(yaw, Eigen::Vector3f::UnitY()));
    const Eigen::Vector3f shift(2.5f, 0.0f, -1.75f);
    LocalMotion moved = prepared.motion;
    RotateWorld(moved, rotation);
    for (int f = 0; f < moved.num_frames(); ++f) moved.SetTranslation(f, 0, moved.translation(f, 0) + shift);
    const std::vector<FrameFeatures> other = ComputeFrameFeatures(
        ForwardKinematics(prepared.skeleton, moved), landmarks, walk.rig.pelvis_up_local, moved.frame_time);
    ASSERT_EQ(other.size(), base.size());
    float worst_position = 0, worst_velocity = 0, worst_scalar = 0, worst_rotation = 0;
    for (size_t f = 0; f < base.size(); ++f) {
      const FrameFeatures& a = base[f];
      const FrameFeatures& b = other[f];
      for (int side = 0; side < 2; ++side) {
        worst_position = std::max({worst_position, (Vec(a.wrist_position[side]) - Vec(b.wrist_position[side])).norm(),
                                   (Vec(a.ankle_position[side]) - Vec(b.ankle_position[side])).norm()});
        worst_velocity = std::max({worst_velocity, (Vec(a.wrist_velocity[side]) - Vec(b.wrist_velocity[side])).norm(),
                                   (Vec(a.ankle_velocity[side]) - Vec(b.ankle_velocity[side])).norm()});
      }
      worst_position = std::max(worst_position, (Vec(a.pelvis_position) - Vec(b.pelvis_position)).norm());
      worst_scalar = std::max(
          {worst_scalar, std::abs(a.pelvis_height - b.pelvis_height), std::abs(a.pelvis_tilt - b.pelvis_tilt)});
      worst_rotation =
          std::max(worst_rotation,
                   static_cast<float>(AngleBetween(Eigen::Quaternionf(a.pelvis_rotation[0], a.pelvis_rotation[1],
                                                                      a.pelvis_rotation[2], a.pelvis_rotation[3]),
                                                   Eigen::Quaternionf(b.pelvis_rotation[0], b.pelvis_rotation[1],
                                                                      b.pelvis_rotation[2], b.pelvis_rotation[3]))));
      // The reference frame moved with the clip.
      EXPECT_NEAR(AngleDifference(b.ref_heading, a.ref_heading + yaw), 0.0f, 1e-4f) << f;
      const Eigen::Vector3f origin = rotation * Eigen::Vector3f(a.ref_origin_x, 0, a.ref_origin_z) + shift;
      EXPECT_NEAR(b.ref_origin_x, origin.x(), 1e-4f) << f;
      EXPECT_NEAR(b.ref_origin_z, origin.z(), 1e-4f) << f;
    }
    EXPECT_LT(worst_position, 1e-4f);
    EXPECT_LT(worst_velocity, 1e-3f);  // float positions ~3 m from the origin, times 30 fps
    EXPECT_LT(worst_scalar, 1e-4f);
    EXPECT_LT(worst_rotation, 1e-4f);
  }
}

TEST(FrameFeaturesTest, LeaningBodyHasTilt) {
  const PreparedWalk walk = PrepareWalk({}, 20);
  LocalMotion leaning = walk.prepared.motion;
  RotateWorld(leaning, Eigen::Quaternionf(Eigen::AngleAxisf(20 * kDegree, Eigen::Vector3f::UnitX())));
  const std::vector<FrameFeatures> features =
      ComputeFrameFeatures(ForwardKinematics(walk.prepared.skeleton, leaning), walk.rig.topology.landmarks,
                           walk.rig.pelvis_up_local, leaning.frame_time);
  ASSERT_EQ(features.size(), 20u);
  for (const FrameFeatures& ff : features) EXPECT_NEAR(ff.pelvis_tilt, 20 * kDegree, 0.5f * kDegree);
}

}  // namespace
}  // namespace mocap

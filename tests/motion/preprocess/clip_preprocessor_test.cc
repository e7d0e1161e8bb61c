#include "motion/preprocess/clip_preprocessor.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "motion/skeleton/forward_kinematics.h"
#include "motion/skeleton/local_motion.h"
#include "tests/support/rotation_checks.h"
#include "tests/support/synthetic_clip.h"

namespace mocap {
namespace {

using testing::kPi;

using testing::MakeWalkingClip;
using testing::SyntheticRigOptions;

// Largest coefficient difference of two quaternions, q and -q being equal.
float QuaternionDistance(const Eigen::Quaternionf& a, const Eigen::Quaternionf& b) {
  return std::min((a.coeffs() - b.coeffs()).cwiseAbs().maxCoeff(), (a.coeffs() + b.coeffs()).cwiseAbs().maxCoeff());
}

float MaxPositionDifference(const GlobalPoses& a, const GlobalPoses& b) {
  EXPECT_EQ(a.num_frames(), b.num_frames());
  EXPECT_EQ(a.num_joints(), b.num_joints());
  if (a.num_frames() != b.num_frames() || a.num_joints() != b.num_joints()) return 1e9f;
  return std::max({(a.px - b.px).abs().maxCoeff(), (a.py - b.py).abs().maxCoeff(), (a.pz - b.pz).abs().maxCoeff()});
}

struct Prepared {
  RigModel rig;
  PreparedClip clip;
};

// Builds the rig from `clip` and prepares `clip` itself; fails the test on errors.
Prepared RigAndPrepare(const BvhClip& clip, const PreprocessOptions& options = {}) {
  Prepared out;
  absl::StatusOr<RigModel> rig = BuildRigModel(clip, options);
  EXPECT_TRUE(rig.ok()) << rig.status();
  if (!rig.ok()) return out;
  out.rig = *std::move(rig);
  absl::StatusOr<PreparedClip> prepared = PrepareClip(clip, out.rig, options);
  EXPECT_TRUE(prepared.ok()) << prepared.status();
  if (prepared.ok()) out.clip = *std::move(prepared);
  return out;
}

GlobalPoses Fk(const PreparedClip& clip) { return ForwardKinematics(clip.skeleton, clip.motion); }

// A copy of `skeleton` with `edit` applied to its joint list.
template <typename Edit>
Skeleton Edited(const Skeleton& skeleton, Edit edit) {
  std::vector<Joint> joints = skeleton.joints();
  edit(joints);
  return Skeleton(std::move(joints));
}

// ---------------------------------------------------------------------------------------------
// Frame rate.

TEST(ClipPreprocessorTest, SixtyFpsBecomesThirtyWithMatchingPoses) {
  const BvhClip clip60 = MakeWalkingClip({}, 61, 1.0 / 60);
  const Prepared p = RigAndPrepare(clip60);
  ASSERT_EQ(p.clip.num_frames(), 31);  // 0 .. 1 s at 30 fps
  EXPECT_EQ(p.clip.source_frames, 61);
  EXPECT_NEAR(p.clip.source_frame_rate, 60.0, 1e-9);
  EXPECT_NEAR(p.clip.motion.frame_time, 1.0 / 30, 1e-12);
  EXPECT_EQ(static_cast<int>(p.clip.features.size()), 31);

  // Even source frames, in metres.
  const LocalMotion source = MotionFromChannels(clip60.skeleton, clip60.channels, clip60.frame_time);
  float worst_rotation = 0, worst_translation = 0;
  for (int k = 0; k < 31; ++k) {
    for (int j = 0; j < source.num_joints(); ++j) {
      worst_rotation =
          std::max(worst_rotation, QuaternionDistance(p.clip.motion.rotation(k, j), source.rotation(2 * k, j)));
    }
    worst_translation =
        std::max(worst_translation, (p.clip.motion.translation(k, 0) - 0.01f * source.translation(2 * k, 0)).norm());
  }
  EXPECT_LT(worst_rotation, 1e-5f);
  EXPECT_LT(worst_translation, 1e-5f);

  // The same walk generated at 30 fps gives the same prepared clip.
  const BvhClip clip30 = MakeWalkingClip({}, 31, 1.0 / 30);
  absl::StatusOr<PreparedClip> direct = PrepareClip(clip30, p.rig, {});
  ASSERT_TRUE(direct.ok()) << direct.status();
  ASSERT_EQ(direct->num_frames(), 31);
  EXPECT_LT(MaxPositionDifference(Fk(*direct), Fk(p.clip)), 1e-4f);
  for (int f = 0; f < 31; ++f) {
    EXPECT_NEAR(direct->features[f].pelvis_height, p.clip.features[f].pelvis_height, 1e-4f);
    EXPECT_NEAR(direct->features[f].wrist_position[0][0], p.clip.features[f].wrist_position[0][0], 1e-4f);
  }
}

TEST(ClipPreprocessorTest, FrameCountsAtOtherRates) {
  const BvhClip base = MakeWalkingClip({}, 30);
  absl::StatusOr<RigModel> rig = BuildRigModel(base, {});
  ASSERT_TRUE(rig.ok()) << rig.status();
  struct Case {
    int frames;
    double frame_time;
    double rate;
    int expected;
  };
  for (const Case& c : {Case{60, 1.0 / 60, 30, 30},  // 59/60 s: 0 .. 29/30
                        Case{30, 1.0 / 30, 30, 30},  // already at the rate
                        Case{30, 1.0 / 30, 60, 59},  // upsampled: 29/30 s at 60 fps
                        Case{120, 1.0 / 120, 30, 30}, Case{2, 1.0 / 30, 30, 2}}) {
    SCOPED_TRACE(::testing::PrintToString(std::vector<double>{double(c.frames), c.frame_time, c.rate}));
    PreprocessOptions options;
    options.frame_rate = c.rate;
    absl::StatusOr<PreparedClip> prepared = PrepareClip(MakeWalkingClip({}, c.frames, c.frame_time), *rig, options);
    ASSERT_TRUE(prepared.ok()) << prepared.status();
    EXPECT_EQ(prepared->num_frames(), c.expected);
    EXPECT_EQ(static_cast<int>(prepared->features.size()), c.expected);
    EXPECT_NEAR(prepared->motion.frame_time, 1.0 / c.rate, 1e-12);
    EXPECT_EQ(prepared->source_frames, c.frames);
  }
}

TEST(ClipPreprocessorTest, ClipsShorterThanTwoFramesAreRefused) {
  const BvhClip base = MakeWalkingClip({}, 30);
  absl::StatusOr<RigModel> rig = BuildRigModel(base, {});
  ASSERT_TRUE(rig.ok()) << rig.status();
  const absl::StatusOr<PreparedClip> one = PrepareClip(MakeWalkingClip({}, 1), *rig, {});
  ASSERT_FALSE(one.ok());
  EXPECT_EQ(one.status().code(), absl::StatusCode::kInvalidArgument) << one.status();
  // Two frames at 60 fps are one frame at 30 fps.
  const absl::StatusOr<PreparedClip> short60 = PrepareClip(MakeWalkingClip({}, 2, 1.0 / 60), *rig, {});
  ASSERT_FALSE(short60.ok());
  EXPECT_EQ(short60.status().code(), absl::StatusCode::kInvalidArgument) << short60.status();
}

// ---------------------------------------------------------------------------------------------
// Units and up axis.

TEST(ClipPreprocessorTest, ConvertsEveryUnitToMetres) {
  const Prepared cm = RigAndPrepare(MakeWalkingClip({}, 30));
  ASSERT_EQ(cm.rig.unit, LengthUnit::kCentimetre);
  const GlobalPoses reference = Fk(cm.clip);
  struct Case {
    double scale;
    LengthUnit unit;
  };
  for (const Case& c : {Case{1.0, LengthUnit::kCentimetre}, Case{0.01, LengthUnit::kMetre},
                        Case{1 / 2.54, LengthUnit::kInch}, Case{10.0, LengthUnit::kMillimetre}}) {
    SCOPED_TRACE(c.scale);
    SyntheticRigOptions options;
    options.length_scale = c.scale;
    const Prepared p = RigAndPrepare(MakeWalkingClip(options, 30));
    EXPECT_EQ(p.rig.unit, c.unit);
    const Skeleton& s = p.clip.skeleton;
    EXPECT_LT((s.joint(s.Find("LeftLeg")).offset - Eigen::Vector3f(0, -0.43f, 0)).norm(), 1e-5f);
    EXPECT_LT((s.joint(s.Find("LeftArm")).offset - Eigen::Vector3f(0.14f, 0, 0)).norm(), 1e-5f);
    EXPECT_LT((s.joint(0).offset - Eigen::Vector3f(0, 0.96f, 0)).norm(), 1e-5f);
    ASSERT_TRUE(s.joint(s.Find("Head")).end_site.has_value());
    EXPECT_LT((*s.joint(s.Find("Head")).end_site - Eigen::Vector3f(0, 0.18f, 0)).norm(), 1e-5f);
    EXPECT_LT(MaxPositionDifference(Fk(p.clip), reference), 1e-4f);
    // Hips around 0.92 m.
    EXPECT_NEAR(p.clip.motion.translation(0, 0).y(), 0.93f, 0.04f);
  }
}

TEST(ClipPreprocessorTest, UnitOverride) {
  PreprocessOptions options;
  options.unit = LengthUnit::kMillimetre;  // the cm clip read as millimetres: a 10x smaller body
  const Prepared p = RigAndPrepare(MakeWalkingClip({}, 30), options);
  EXPECT_EQ(p.rig.unit, LengthUnit::kMillimetre);
  EXPECT_NEAR(p.clip.motion.translation(0, 0).y(), 0.093f, 0.004f);
}

TEST(ClipPreprocessorTest, EachPerformerKeepsItsOwnOffsets) {
  const BvhClip first = MakeWalkingClip({}, 30);
  absl::StatusOr<RigModel> rig = BuildRigModel(first, {});
  ASSERT_TRUE(rig.ok()) << rig.status();
  SyntheticRigOptions taller;
  taller.length_scale = 1.1;
  absl::StatusOr<PreparedClip> prepared = PrepareClip(MakeWalkingClip(taller, 30), *rig, {});
  ASSERT_TRUE(prepared.ok()) << prepared.status();
  const Skeleton& s = prepared->skeleton;
  EXPECT_NEAR(s.joint(s.Find("LeftLeg")).offset.y(), -0.473f, 1e-5f);
  EXPECT_NEAR(s.joint(s.Find("Neck")).offset.y(), 0.242f, 1e-5f);
  // The rig keeps the first clip's file offsets.
  EXPECT_NEAR(rig->skeleton.joint(rig->skeleton.Find("LeftLeg")).offset.y(), -43.0f, 1e-4f);
}

// Issue #23: CMU's ASF-converted units (1 unit = 1/0.45 inch) are detected and give a person of
// a person's size (read as inches it was 0.9 m tall).
TEST(ClipPreprocessorTest, ReadsCmuUnitsAtAPlausibleHeight) {
  SyntheticRigOptions cmu;
  cmu.length_scale = 0.45 / 2.54;  // centimetres to CMU units: the leg is ~15 units
  const Prepared p = RigAndPrepare(MakeWalkingClip(cmu, 30));
  EXPECT_EQ(p.rig.unit, LengthUnit::kCmuUnit);
  EXPECT_TRUE(p.rig.topology.unit_detected);
  EXPECT_NEAR(p.rig.topology.leg_length * MetresPerUnit(p.rig.unit), 0.85, 0.01);
  const Skeleton& s = p.clip.skeleton;
  EXPECT_LT((s.joint(s.Find("LeftLeg")).offset - Eigen::Vector3f(0, -0.43f, 0)).norm(), 1e-5f);
  // Hips around 0.92 m, as the centimetre walk's.
  EXPECT_NEAR(p.clip.motion.translation(0, 0).y(), 0.93f, 0.04f);
  ASSERT_FALSE(p.clip.features.empty());
  EXPECT_NEAR(p.clip.features[0].pelvis_height, 0.92f, 0.06f);
}

// A first clip whose body is no person's size in its detected unit: refused, naming --units.
TEST(ClipPreprocessorTest, RefusesAFirstClipAtTwiceTheScale) {
  SyntheticRigOptions twice;
  twice.length_scale = 2.0;  // centimetres, exported at twice scale: 1.7 m legs
  const absl::StatusOr<RigModel> rig = BuildRigModel(MakeWalkingClip(twice, 30), {});
  ASSERT_FALSE(rig.ok());
  EXPECT_EQ(rig.status().code(), absl::StatusCode::kInvalidArgument) << rig.status();
  EXPECT_NE(rig.status().message().find("--units"), std::string_view::npos) << rig.status();
}

// Issue #23: every clip is checked, not only the one the rig is built from. A later clip of the same
// rig exported at twice scale, or in another unit, would be stored as a 3.5 m or a 0.02 m person.
TEST(ClipPreprocessorTest, RefusesALaterClipAtTwiceTheScale) {
  const absl::StatusOr<RigModel> rig = BuildRigModel(MakeWalkingClip({}, 30), {});
  ASSERT_TRUE(rig.ok()) << rig.status();
  ASSERT_EQ(rig->unit, LengthUnit::kCentimetre);
  SyntheticRigOptions twice;
  twice.length_scale = 2.0;
  const absl::StatusOr<PreparedClip> prepared = PrepareClip(MakeWalkingClip(twice, 30), *rig, {});
  ASSERT_FALSE(prepared.ok());
  EXPECT_EQ(prepared.status().code(), absl::StatusCode::kInvalidArgument) << prepared.status();
  EXPECT_NE(prepared.status().message().find("--units"), std::string_view::npos) << prepared.status();
  EXPECT_NE(prepared.status().message().find("'cm'"), std::string_view::npos) << prepared.status();
  // The same walk at the rig's own scale is fine.
  EXPECT_TRUE(PrepareClip(MakeWalkingClip({}, 30), *rig, {}).ok());
}

TEST(ClipPreprocessorTest, RefusesALaterClipInAnotherUnit) {
  const absl::StatusOr<RigModel> rig = BuildRigModel(MakeWalkingClip({}, 30), {});
  ASSERT_TRUE(rig.ok()) << rig.status();
  for (double scale : {0.01, 1 / 2.54, 10.0}) {  // metres, inches, millimetres read as centimetres
    SCOPED_TRACE(scale);
    SyntheticRigOptions other;
    other.length_scale = scale;
    const absl::StatusOr<PreparedClip> prepared = PrepareClip(MakeWalkingClip(other, 30), *rig, {});
    ASSERT_FALSE(prepared.ok());
    EXPECT_EQ(prepared.status().code(), absl::StatusCode::kInvalidArgument) << prepared.status();
    EXPECT_NE(prepared.status().message().find("--units"), std::string_view::npos) << prepared.status();
  }
}

// A declared unit is the caller's word for the rig's own body, however small (UnitOverride): later
// clips of that body are accepted, a clip at twice its size is not.
TEST(ClipPreprocessorTest, DeclaredUnitChecksLaterClipsAgainstTheRigsBody) {
  PreprocessOptions options;
  options.unit = LengthUnit::kMillimetre;  // a 0.085 m leg
  const absl::StatusOr<RigModel> rig = BuildRigModel(MakeWalkingClip({}, 30), options);
  ASSERT_TRUE(rig.ok()) << rig.status();
  SyntheticRigOptions taller;
  taller.length_scale = 1.1;
  EXPECT_TRUE(PrepareClip(MakeWalkingClip(taller, 30), *rig, options).ok());
  SyntheticRigOptions twice;
  twice.length_scale = 2.0;
  const absl::StatusOr<PreparedClip> prepared = PrepareClip(MakeWalkingClip(twice, 30), *rig, options);
  ASSERT_FALSE(prepared.ok());
  EXPECT_NE(prepared.status().message().find("--units"), std::string_view::npos) << prepared.status();
}

TEST(ClipPreprocessorTest, ZUpWorldBecomesYUp) {
  // The plain walk with the whole world turned so that up is +Z (Y -> Z).
  const BvhClip plain = MakeWalkingClip({}, 30);
  LocalMotion motion = MotionFromChannels(plain.skeleton, plain.channels, plain.frame_time);
  RotateWorld(motion, Eigen::Quaternionf(Eigen::AngleAxisf(kPi / 2, Eigen::Vector3f::UnitX())));
  BvhClip z_up_world = plain;
  z_up_world.channels = ChannelsFromMotion(plain.skeleton, motion);
  {
    const GlobalPoses poses = ForwardKinematics(plain.skeleton, motion);
    ASSERT_GT(poses.pz(0, 0), 80.0f);  // the Hips are 90 cm up +Z
  }

  const Prepared reference = RigAndPrepare(plain);
  const Prepared turned = RigAndPrepare(z_up_world);
  EXPECT_EQ(turned.rig.topology.up_axis, 2);
  EXPECT_EQ(turned.rig.topology.up_sign, 1);
  EXPECT_LT((turned.rig.to_y_up * Eigen::Vector3f::UnitZ() - Eigen::Vector3f::UnitY()).norm(), 1e-6f);
  EXPECT_TRUE(reference.rig.to_y_up.isApprox(Eigen::Quaternionf::Identity()));
  const GlobalPoses a = Fk(reference.clip), b = Fk(turned.clip);
  EXPECT_LT(MaxPositionDifference(a, b), 1e-4f);
  for (int f = 0; f < 30; ++f) {
    EXPECT_NEAR(turned.clip.features[f].pelvis_height, reference.clip.features[f].pelvis_height, 1e-4f);
    EXPECT_NEAR(turned.clip.features[f].ankle_position[0][1], reference.clip.features[f].ankle_position[0][1], 1e-4f);
    EXPECT_NEAR(turned.clip.features[f].pelvis_tilt, reference.clip.features[f].pelvis_tilt, 1e-3f);
  }
}

TEST(ClipPreprocessorTest, ZUpHierarchyUnderRlBoneRoot) {
  SyntheticRigOptions z_up;
  z_up.z_up = true;
  const Prepared plain = RigAndPrepare(MakeWalkingClip({}, 30));
  const Prepared rl = RigAndPrepare(MakeWalkingClip(z_up, 30));
  EXPECT_EQ(rl.rig.topology.up_axis, 1);
  EXPECT_EQ(rl.rig.topology.rest_up_axis, 2);
  // The Hips' local up is +Z in the Z-up hierarchy, +Y in the plain one.
  EXPECT_GT(rl.rig.pelvis_up_local.z(), 0.99f) << rl.rig.pelvis_up_local.transpose();
  EXPECT_GT(plain.rig.pelvis_up_local.y(), 0.99f) << plain.rig.pelvis_up_local.transpose();
  // Same world positions, joint by joint (RL_BoneRoot shifts the indices by one).
  const GlobalPoses a = Fk(plain.clip), b = Fk(rl.clip);
  const Skeleton& sa = plain.clip.skeleton;
  const Skeleton& sb = rl.clip.skeleton;
  float worst = 0;
  for (int j = 0; j < sa.num_joints(); ++j) {
    const int k = sb.Find(sa.joint(j).name);
    ASSERT_GE(k, 0);
    for (int f = 0; f < 30; ++f) worst = std::max(worst, (a.position(f, j) - b.position(f, k)).norm());
  }
  EXPECT_LT(worst, 1e-4f);
  for (int f = 0; f < 30; ++f) {
    EXPECT_NEAR(rl.clip.features[f].pelvis_tilt, plain.clip.features[f].pelvis_tilt, 1e-3f);
    EXPECT_NEAR(rl.clip.features[f].wrist_position[1][2], plain.clip.features[f].wrist_position[1][2], 1e-4f);
  }
}

// ---------------------------------------------------------------------------------------------
// Pose encoding.

class ClipPreprocessorEncodingTest : public ::testing::TestWithParam<int> {};

TEST_P(ClipPreprocessorEncodingTest, EncodeDecodeRoundTrip) {
  SyntheticRigOptions options;
  options.z_up = (GetParam() & 2) != 0;
  options.fingers_and_toes = (GetParam() & 4) != 0;
  options.twist_bones = (GetParam() & 8) != 0;
  options.rotation_order = (GetParam() & 16) != 0 ? "XYZ" : "ZXY";
  const Prepared p = RigAndPrepare(MakeWalkingClip(options, 40));
  const LocalMotion& motion = p.clip.motion;
  const int joints = motion.num_joints();
  ASSERT_EQ(static_cast<int>(p.rig.reference_rotations.size()), joints);
  for (const Eigen::Quaternionf& q : p.rig.reference_rotations) EXPECT_NEAR(q.norm(), 1.0f, 1e-5f);

  const std::vector<float> encoded = EncodePoses(motion, p.rig);
  ASSERT_EQ(EncodedPoseFloats(joints), 3 + 3 * joints);
  ASSERT_EQ(encoded.size(), static_cast<size_t>(motion.num_frames() * EncodedPoseFloats(joints)));
  // Root translation first, in metres.
  EXPECT_NEAR(encoded[0], motion.tx(0, 0), 1e-7f);
  EXPECT_NEAR(encoded[1], motion.ty(0, 0), 1e-7f);
  EXPECT_NEAR(encoded[2], motion.tz(0, 0), 1e-7f);
  // Relative to the mean pose, the walk's rotations are small.
  double mean_angle = 0;
  for (int f = 0; f < motion.num_frames(); ++f) {
    for (int j = 0; j < joints; ++j) {
      const float* v = &encoded[f * EncodedPoseFloats(joints) + 3 + 3 * j];
      mean_angle += Eigen::Vector3f(v[0], v[1], v[2]).norm() / (motion.num_frames() * joints);
    }
  }
  EXPECT_LT(mean_angle, 0.3);

  const LocalMotion decoded = DecodePoses(encoded, p.clip.skeleton, p.rig, motion.frame_time);
  ASSERT_EQ(decoded.num_frames(), motion.num_frames());
  ASSERT_EQ(decoded.num_joints(), joints);
  EXPECT_EQ(decoded.frame_time, motion.frame_time);
  float worst = 0;
  for (int f = 0; f < motion.num_frames(); ++f) {
    for (int j = 0; j < joints; ++j) {
      worst = std::max(worst, QuaternionDistance(decoded.rotation(f, j), motion.rotation(f, j)));
    }
  }
  EXPECT_LT(worst, 1e-5f);
  EXPECT_LT(MaxPositionDifference(ForwardKinematics(p.clip.skeleton, decoded), Fk(p.clip)), 1e-4f);
}

INSTANTIATE_TEST_SUITE_P(Rigs, ClipPreprocessorEncodingTest, ::testing::Values(0, 2, 4 | 8, 2 | 4 | 8 | 16, 16));

TEST(ClipPreprocessorTest, EncodingHandlesHalfTurnsAndIdentity) {
  const Prepared p = RigAndPrepare(MakeWalkingClip({}, 6));
  LocalMotion motion = p.clip.motion;
  const int joint = 7;
  const Eigen::Quaternionf& reference = p.rig.reference_rotations[joint];
  const Eigen::Vector3f axis = Eigen::Vector3f(0.3f, -0.5f, 0.8f).normalized();
  // Exactly the reference, nearly a half turn, a half turn stored with w < 0, a tiny angle.
  const Eigen::Quaternionf cases[] = {
      reference,
      reference * Eigen::Quaternionf(Eigen::AngleAxisf(3.1f, axis)),
      Eigen::Quaternionf(-(reference * Eigen::Quaternionf(Eigen::AngleAxisf(kPi - 1e-3f, axis))).coeffs()),
      reference * Eigen::Quaternionf(Eigen::AngleAxisf(1e-6f, axis)),
      reference * Eigen::Quaternionf(Eigen::AngleAxisf(-2.0f, axis)),
  };
  for (int f = 0; f < 5; ++f) motion.SetRotation(f, joint, cases[f]);
  const LocalMotion decoded = DecodePoses(EncodePoses(motion, p.rig), p.clip.skeleton, p.rig, motion.frame_time);
  for (int f = 0; f < 5; ++f) {
    EXPECT_LT(QuaternionDistance(decoded.rotation(f, joint), cases[f]), 1e-5f) << f;
    EXPECT_NEAR(decoded.rotation(f, joint).norm(), 1.0f, 1e-5f) << f;
  }
}

TEST(ClipPreprocessorTest, AnimatedJointsCarryTheirOwnTranslations) {
  SyntheticRigOptions options;
  options.extra_root = true;
  const Prepared p = RigAndPrepare(MakeWalkingClip(options, 30));
  const int hips = p.clip.skeleton.Find("Hips");
  ASSERT_EQ(hips, 1);
  EXPECT_EQ(p.clip.animated_joints, std::vector<int>{hips});
  // Decoding takes non-root translations from the offsets: the store must put the animated
  // joints' translations back, and then the clip is whole again.
  LocalMotion decoded =
      DecodePoses(EncodePoses(p.clip.motion, p.rig), p.clip.skeleton, p.rig, p.clip.motion.frame_time);
  EXPECT_GT(MaxPositionDifference(ForwardKinematics(p.clip.skeleton, decoded), Fk(p.clip)), 0.5f);
  for (int f = 0; f < decoded.num_frames(); ++f) {
    for (int j : p.clip.animated_joints) decoded.SetTranslation(f, j, p.clip.motion.translation(f, j));
  }
  EXPECT_LT(MaxPositionDifference(ForwardKinematics(p.clip.skeleton, decoded), Fk(p.clip)), 1e-4f);
}

TEST(ClipPreprocessorTest, AnimatedJointsOfOtherRigs) {
  for (int bits : {0, 2, 4 | 8, 16, 2 | 16, 1 | 16, 1 | 2 | 16}) {
    const SyntheticRigOptions options = testing::SyntheticRigFromBits(bits);
    SCOPED_TRACE(bits);
    const Prepared p = RigAndPrepare(MakeWalkingClip(options, 20));
    if (options.extra_root) {
      EXPECT_EQ(p.clip.animated_joints, std::vector<int>{p.clip.skeleton.Find("Hips")});
    } else {
      // Position channels equal to the OFFSETs do not animate anything; the root is not listed.
      EXPECT_TRUE(p.clip.animated_joints.empty()) << p.clip.animated_joints.size();
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Rig checks.

TEST(ClipPreprocessorTest, RefusesRenamedJoint) {
  const BvhClip first = MakeWalkingClip({}, 20);
  absl::StatusOr<RigModel> rig = BuildRigModel(first, {});
  ASSERT_TRUE(rig.ok()) << rig.status();
  BvhClip renamed = first;
  renamed.skeleton = Edited(first.skeleton, [](std::vector<Joint>& joints) {
    for (Joint& joint : joints) {
      if (joint.name == "LeftForeArm") joint.name = "LeftElbow";
    }
  });
  const absl::StatusOr<PreparedClip> prepared = PrepareClip(renamed, *rig, {});
  ASSERT_FALSE(prepared.ok());
  EXPECT_EQ(prepared.status().code(), absl::StatusCode::kFailedPrecondition) << prepared.status();
  EXPECT_NE(prepared.status().message().find("LeftElbow"), std::string_view::npos) << prepared.status();
  EXPECT_NE(prepared.status().message().find("LeftForeArm"), std::string_view::npos) << prepared.status();
}

TEST(ClipPreprocessorTest, RefusesReparentedJoint) {
  const BvhClip first = MakeWalkingClip({}, 20);
  absl::StatusOr<RigModel> rig = BuildRigModel(first, {});
  ASSERT_TRUE(rig.ok()) << rig.status();
  BvhClip moved = first;
  const int neck = first.skeleton.Find("Neck");
  moved.skeleton = Edited(first.skeleton, [neck](std::vector<Joint>& joints) {
    for (Joint& joint : joints) {
      if (joint.name == "RightShoulder") joint.parent = neck;
    }
  });
  ASSERT_TRUE(moved.skeleton.Validate().ok());
  const absl::StatusOr<PreparedClip> prepared = PrepareClip(moved, *rig, {});
  ASSERT_FALSE(prepared.ok());
  EXPECT_EQ(prepared.status().code(), absl::StatusCode::kFailedPrecondition) << prepared.status();
  EXPECT_NE(prepared.status().message().find("RightShoulder"), std::string_view::npos) << prepared.status();
}

TEST(ClipPreprocessorTest, RefusesExtraJointAndNamesIt) {
  const BvhClip first = MakeWalkingClip({}, 20);
  absl::StatusOr<RigModel> rig = BuildRigModel(first, {});
  ASSERT_TRUE(rig.ok()) << rig.status();

  // A prop joint (no channels) appended under the right hand: the channel layout is unchanged.
  BvhClip with_prop = first;
  const int hand = first.skeleton.Find("RightHand");
  with_prop.skeleton = Edited(first.skeleton, [hand](std::vector<Joint>& joints) {
    joints.push_back(Joint{.name = "Prop", .parent = hand, .offset = Eigen::Vector3f(10, 0, 0)});
  });
  ASSERT_TRUE(with_prop.skeleton.Validate().ok());
  ASSERT_EQ(with_prop.skeleton.num_channels(), first.skeleton.num_channels());
  const absl::StatusOr<PreparedClip> prop = PrepareClip(with_prop, *rig, {});
  ASSERT_FALSE(prop.ok());
  EXPECT_EQ(prop.status().code(), absl::StatusCode::kFailedPrecondition) << prop.status();
  EXPECT_NE(prop.status().message().find("Prop"), std::string_view::npos) << prop.status();

  // Fingers inserted in the middle of the hierarchy: the first joint that differs is named.
  SyntheticRigOptions fingers;
  fingers.fingers_and_toes = true;
  const absl::StatusOr<PreparedClip> inserted = PrepareClip(MakeWalkingClip(fingers, 20), *rig, {});
  ASSERT_FALSE(inserted.ok());
  EXPECT_EQ(inserted.status().code(), absl::StatusCode::kFailedPrecondition) << inserted.status();
  EXPECT_NE(inserted.status().message().find("LeftHandThumb1"), std::string_view::npos) << inserted.status();
}

TEST(ClipPreprocessorTest, AcceptsOtherChannelOrdersOfTheSameRig) {
  const BvhClip first = MakeWalkingClip({}, 20);
  absl::StatusOr<RigModel> rig = BuildRigModel(first, {});
  ASSERT_TRUE(rig.ok()) << rig.status();
  SyntheticRigOptions other;
  other.rotation_order = "YXZ";
  other.position_channels_everywhere = true;
  absl::StatusOr<PreparedClip> prepared = PrepareClip(MakeWalkingClip(other, 20), *rig, {});
  ASSERT_TRUE(prepared.ok()) << prepared.status();
  absl::StatusOr<PreparedClip> same = PrepareClip(first, *rig, {});
  ASSERT_TRUE(same.ok()) << same.status();
  EXPECT_LT(MaxPositionDifference(Fk(*prepared), Fk(*same)), 1e-4f);
}

TEST(ClipPreprocessorTest, BuildRigModelRefusesNonHumanoid) {
  BvhClip chain;
  std::vector<Joint> joints;
  for (int j = 0; j < 5; ++j) {
    joints.push_back(Joint{.name = "J" + std::to_string(j),
                           .parent = j - 1,
                           .offset = Eigen::Vector3f(0, 20, 0),
                           .channels = {ChannelType::kZrotation, ChannelType::kXrotation, ChannelType::kYrotation}});
  }
  chain.skeleton = Skeleton(std::move(joints));
  chain.frame_time = 1.0 / 30;
  chain.channels.setZero(10, chain.skeleton.num_channels());
  const absl::StatusOr<RigModel> rig = BuildRigModel(chain, {});
  ASSERT_FALSE(rig.ok());
  EXPECT_EQ(rig.status().code(), absl::StatusCode::kFailedPrecondition) << rig.status();
}

}  // namespace
}  // namespace mocap

// The change of basis between a caller's frame and the native one (motion/frames): axes,
// handedness, units, floor, and rotations R' = C·R·C⁻¹ that keep forward kinematics consistent.
#include "motion/frames/frame_transform.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include <Eigen/LU>

#include "motion/frames/input_frame.h"

namespace mocap {
namespace {

constexpr UpAxis kUps[] = {UpAxis::kPosX, UpAxis::kNegX, UpAxis::kPosY, UpAxis::kNegY, UpAxis::kPosZ, UpAxis::kNegZ};
constexpr LengthUnit kUnits[] = {LengthUnit::kMetre, LengthUnit::kCentimetre, LengthUnit::kMillimetre,
                                 LengthUnit::kInch};

std::vector<FrameConvention> AllConventions() {
  std::vector<FrameConvention> all;
  for (LengthUnit unit : kUnits) {
    for (UpAxis up : kUps) {
      for (Handedness handedness : {Handedness::kRight, Handedness::kLeft}) all.push_back({unit, up, handedness});
    }
  }
  return all;
}

Eigen::Vector3f Axis(int index, float sign) { return sign * Eigen::Vector3f::Unit(index); }

TEST(NativeBasisTest, TurnsTheUpAxisUpAndFlipsHandednessOnlyForLeftHandedFrames) {
  for (UpAxis up : kUps) {
    for (Handedness handedness : {Handedness::kRight, Handedness::kLeft}) {
      const Eigen::Matrix3f c = NativeBasis(up, handedness);
      SCOPED_TRACE(std::string(UpAxisName(up)) + " " + std::string(HandednessName(handedness)));
      EXPECT_TRUE((c * c.transpose()).isIdentity(0.0f));
      EXPECT_EQ(c.determinant(), handedness == Handedness::kRight ? 1.0f : -1.0f);
      EXPECT_TRUE((c * Axis(UpAxisIndex(up), UpAxisSign(up))).isApprox(Eigen::Vector3f::UnitY()));
    }
  }
}

TEST(NativeBasisTest, MatchesTheUsualConversionsOfKnownEngines) {
  const Eigen::Vector3f p(1, 2, 3);
  // Unity (left-handed, Y up): z is negated.
  EXPECT_EQ(NativeBasis(UpAxis::kPosY, Handedness::kLeft) * p, Eigen::Vector3f(1, 2, -3));
  // Blender (right-handed, Z up): (x, z, −y).
  EXPECT_EQ(NativeBasis(UpAxis::kPosZ, Handedness::kRight) * p, Eigen::Vector3f(1, 3, -2));
  // Unreal (left-handed, Z up: x forward, y right): (x, z, y).
  EXPECT_EQ(NativeBasis(UpAxis::kPosZ, Handedness::kLeft) * p, Eigen::Vector3f(1, 3, 2));
  // MediaPipe world landmarks (right-handed, y down): (x, −y, −z).
  EXPECT_EQ(NativeBasis(UpAxis::kNegY, Handedness::kRight) * p, Eigen::Vector3f(1, -2, -3));
  EXPECT_EQ(NativeBasis(UpAxis::kPosY, Handedness::kRight) * p, p);
}

TEST(FrameTransformTest, UnitsAndFloorPutTheCallersFloorAtZero) {
  // Unreal: centimetres, floor at z = 12 cm; a wrist 100 cm above it is 1 m up.
  const FrameTransform unreal({LengthUnit::kCentimetre, UpAxis::kPosZ, Handedness::kLeft}, 12.0);
  EXPECT_TRUE(unreal.PositionToNative({30, -40, 112}).isApprox(Eigen::Vector3f(0.3f, 1.0f, -0.4f)));
  EXPECT_NEAR(unreal.floor_native(), 0.12f, 1e-6);
  // MediaPipe: y down, the floor 0.9 m below the hips' origin is y = +0.9; the origin is 0.9 m up.
  const FrameTransform mediapipe({LengthUnit::kMetre, UpAxis::kNegY, Handedness::kRight}, 0.9);
  EXPECT_NEAR(mediapipe.PositionToNative({0.2f, 0.9f, 0.1f}).y(), 0.0f, 1e-6);
  EXPECT_NEAR(mediapipe.PositionToNative({0.0f, 0.0f, 0.0f}).y(), 0.9f, 1e-6);
  EXPECT_NEAR(mediapipe.PositionToNative({0.0f, -0.5f, 0.0f}).y(), 1.4f, 1e-6);  // 0.5 above the hips
  // Offsets scale and turn but ignore the floor.
  EXPECT_TRUE(unreal.VectorToNative({0, 0, 50}).isApprox(Eigen::Vector3f(0, 0.5f, 0)));
  EXPECT_FLOAT_EQ(unreal.LengthFromNative(1.0f), 100.0f);
}

TEST(FrameTransformTest, EveryConventionRoundTripsAndReportsItsFloorBack) {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> coordinate(-3.0f, 3.0f);
  for (const FrameConvention& convention : AllConventions()) {
    const double floor = coordinate(random) / MetresPerUnit(convention.unit);
    const FrameTransform transform(convention, floor);
    SCOPED_TRACE(std::string(UnitName(convention.unit)) + " " + std::string(UpAxisName(convention.up)) + " " +
                 std::string(HandednessName(convention.handedness)));
    EXPECT_NEAR(FloorHeightFromNative(convention, transform.floor_native()), floor, 1e-4 * std::abs(floor) + 1e-6);
    for (int i = 0; i < 20; ++i) {  // a room's worth of positions in the caller's unit
      const Eigen::Vector3f p =
          Eigen::Vector3f(coordinate(random), coordinate(random), coordinate(random)) / MetresPerUnit(convention.unit);
      EXPECT_TRUE(transform.PositionFromNative(transform.PositionToNative(p)).isApprox(p, 1e-5f));
      EXPECT_TRUE(transform.VectorFromNative(transform.VectorToNative(p)).isApprox(p, 1e-5f));
      const Eigen::Quaternionf q = Eigen::Quaternionf::UnitRandom();
      EXPECT_TRUE(transform.RotationFromNative(transform.RotationToNative(q)).isApprox(q, 1e-6f));
    }
  }
}

TEST(FrameTransformTest, RotationsAreConjugatedAndStayProperAlsoAcrossHandedness) {
  for (const FrameConvention& convention : AllConventions()) {
    const FrameTransform transform(convention, 0.0);
    const Eigen::Matrix3f c = transform.basis();
    for (int i = 0; i < 10; ++i) {
      const Eigen::Quaternionf q = Eigen::Quaternionf::UnitRandom();
      const Eigen::Quaternionf converted = transform.RotationToNative(q);
      const Eigen::Matrix3f expected = c * q.toRotationMatrix() * c.transpose();  // C·R·C⁻¹
      EXPECT_TRUE(converted.toRotationMatrix().isApprox(expected, 1e-5f));
      EXPECT_NEAR(converted.toRotationMatrix().determinant(), 1.0f, 1e-5f);
      EXPECT_NEAR(converted.norm(), 1.0f, 1e-6f);
      // A rotated vector converts like the rotation applied to the converted vector.
      const Eigen::Vector3f v(0.3f, -0.2f, 0.5f);
      EXPECT_TRUE(transform.VectorToNative(q * v).isApprox(converted * transform.VectorToNative(v), 1e-5f));
    }
  }
}

// A chain given by a root position, local rotations and offsets, as a skeleton and frame are.
std::vector<Eigen::Vector3f> ChainPositions(const Eigen::Vector3f& root,
                                            const std::vector<Eigen::Quaternionf>& rotations,
                                            const std::vector<Eigen::Vector3f>& offsets) {
  std::vector<Eigen::Vector3f> positions = {root};
  Eigen::Quaternionf global = rotations[0];
  for (size_t j = 1; j < rotations.size(); ++j) {
    positions.push_back(positions.back() + global * offsets[j]);
    global = global * rotations[j];
  }
  return positions;
}

TEST(FrameTransformTest, ConvertingAPoseJointByJointEqualsConvertingItsForwardKinematics) {
  std::mt19937 random(3);
  std::uniform_real_distribution<float> length(-0.4f, 0.4f);
  for (const FrameConvention& convention : AllConventions()) {
    const FrameTransform transform(convention, 25.0);
    std::vector<Eigen::Quaternionf> rotations;
    std::vector<Eigen::Vector3f> offsets;
    for (int j = 0; j < 6; ++j) {
      rotations.push_back(Eigen::Quaternionf::UnitRandom());
      offsets.emplace_back(length(random), length(random), length(random));
    }
    const Eigen::Vector3f root(0.2f, 0.95f, -1.3f);
    const std::vector<Eigen::Vector3f> native = ChainPositions(root, rotations, offsets);
    std::vector<Eigen::Quaternionf> caller_rotations;
    std::vector<Eigen::Vector3f> caller_offsets;
    for (int j = 0; j < 6; ++j) {
      caller_rotations.push_back(transform.RotationFromNative(rotations[j]));
      caller_offsets.push_back(transform.VectorFromNative(offsets[j]));
    }
    const std::vector<Eigen::Vector3f> caller =
        ChainPositions(transform.PositionFromNative(root), caller_rotations, caller_offsets);
    for (size_t j = 0; j < native.size(); ++j) {
      EXPECT_TRUE(transform.PositionToNative(caller[j]).isApprox(native[j], 1e-4f)) << j;
    }
  }
}

TEST(InputFrameTest, PresetsAreFoundByNameAndSayWhatTheyAssume) {
  ASSERT_TRUE(FindInputFramePreset("UNREAL"));
  const InputFrame unreal = FindInputFramePreset("unreal")->frame;
  EXPECT_EQ(unreal.convention.unit, LengthUnit::kCentimetre);
  EXPECT_EQ(unreal.convention.up, UpAxis::kPosZ);
  EXPECT_EQ(unreal.convention.handedness, Handedness::kLeft);
  EXPECT_EQ(FindInputFramePreset("unity")->frame.convention.handedness, Handedness::kLeft);
  EXPECT_TRUE(FindInputFramePreset("openxr-local")->frame.floor.calibrate);
  EXPECT_FALSE(FindInputFramePreset("openxr-local-floor")->frame.floor.calibrate);
  EXPECT_EQ(FindInputFramePreset("mediapipe-world")->frame.convention.up, UpAxis::kNegY);
  EXPECT_TRUE(IsNativeFrame(FindInputFramePreset("native")->frame));
  EXPECT_FALSE(FindInputFramePreset("maya"));
  for (const InputFramePreset& preset : InputFramePresets()) {
    EXPECT_FALSE(preset.description.empty());
    EXPECT_TRUE(ValidateInputFrame(preset.frame).ok()) << preset.name;
  }
}

TEST(InputFrameTest, DeclarationsOutOfRangeAreRefusedNamingTheField) {
  InputFrame frame;
  frame.floor.height = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(ValidateInputFrame(frame).message().find("floor_height"), std::string_view::npos);
  frame = {};
  frame.tracked_device = true;
  frame.device_offset = {0, 0, 0.6f};
  EXPECT_NE(ValidateInputFrame(frame).message().find("device_offset"), std::string_view::npos);
  frame.convention.unit = LengthUnit::kCentimetre;
  frame.device_offset = {0, 0, 30};  // 0.3 m
  EXPECT_TRUE(ValidateInputFrame(frame).ok());
  EXPECT_TRUE(
      DeviceToWrist({1, 1, 1}, Eigen::Quaternionf(Eigen::AngleAxisf(M_PI / 2, Eigen::Vector3f::UnitY())), {0, 0, 1})
          .isApprox(Eigen::Vector3f(2, 1, 1)));
  // A device gripped beyond the wrist, its orientation not sent: up to 0.3 m, not beside one that is.
  frame = {};
  frame.convention.unit = LengthUnit::kCentimetre;
  frame.grip_offset = 9;
  EXPECT_TRUE(ValidateInputFrame(frame).ok());
  for (const float grip : {-1.0f, 31.0f, std::numeric_limits<float>::quiet_NaN()}) {
    frame.grip_offset = grip;
    EXPECT_NE(ValidateInputFrame(frame).message().find("grip_offset"), std::string_view::npos) << grip;
  }
  frame.grip_offset = 9;
  frame.tracked_device = true;
  EXPECT_NE(ValidateInputFrame(frame).message().find("tracked_device"), std::string_view::npos);
}

TEST(InputFrameTest, AxisAndHandednessNamesParse) {
  EXPECT_EQ(ParseUpAxis("z"), UpAxis::kPosZ);
  EXPECT_EQ(ParseUpAxis("-y"), UpAxis::kNegY);
  EXPECT_EQ(ParseUpAxis("+X"), UpAxis::kPosX);
  EXPECT_FALSE(ParseUpAxis("w"));
  EXPECT_EQ(ParseHandedness("LH"), Handedness::kLeft);
  EXPECT_EQ(ParseHandedness("right"), Handedness::kRight);
  EXPECT_FALSE(ParseHandedness("both"));
}

}  // namespace
}  // namespace mocap

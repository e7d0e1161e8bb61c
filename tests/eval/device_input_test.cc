// Device-like input (eval/device_input.h): each device sends what it says, and nothing else.
#include "eval/device_input.h"

#include <gtest/gtest.h>

#include <cmath>

namespace mocap::eval {
namespace {

// 4 s at 30 fps: the left wrist moves along x at 1 m/s (more than a 1 cm grid step per sample at
// 72 Hz), the right one stays.
LandmarkTruth MovingWrists() {
  LandmarkTruth truth{.frame_time = 1.0 / 30.0, .positions = {}};
  for (int f = 0; f <= 120; ++f) {
    std::array<Eigen::Vector3f, kNumScoredLandmarks> frame;
    frame.fill(Eigen::Vector3f(0.0f, 1.0f, 0.0f));
    frame[kLeftWristLandmark] = Eigen::Vector3f(f / 30.0f, 1.2f, 0.3f);
    frame[kRightWristLandmark] = Eigen::Vector3f(-0.2f, 1.1f, 0.3f);
    truth.positions.push_back(frame);
  }
  return truth;
}

TEST(DeviceInputTest, LabInputIsTheClipsFramesPlusNoise) {
  const auto samples = DeviceSamples(MovingWrists(), {}, 0.0, 1);
  ASSERT_EQ(samples.size(), 121u);
  EXPECT_NEAR(samples[60].time, 2.0, 1e-9);
  EXPECT_NEAR(samples[60].left.x(), 2.0f, 1e-6);
}

TEST(DeviceInputTest, ControllersQuantiseRepeatAndKeepTheirRate) {
  const DeviceModel controllers = StandardDevices()[0];
  ASSERT_EQ(controllers.name, "controllers_72hz");
  const auto samples = DeviceSamples(MovingWrists(), controllers, 0.0, 7);
  ASSERT_EQ(samples.size(), 4u * 72 + 1);
  int repeats = 0;
  for (size_t i = 0; i < samples.size(); ++i) {
    EXPECT_NEAR(samples[i].time, i / 72.0, 1e-9);
    for (float x : {samples[i].left.x(), samples[i].left.y(), samples[i].right.z()}) {
      EXPECT_NEAR(x * 100.0f, std::round(x * 100.0f), 1e-3) << "on the 1 cm grid";
    }
    const bool repeated = i > 0 && samples[i].left == samples[i - 1].left;
    // A fresh sample is the truth at its own time, to the grid (a repeat holds an older one).
    if (!repeated) {
      EXPECT_LE(std::abs(samples[i].left.x() - static_cast<float>(samples[i].time)), 0.0051f) << i;
    }
    repeats += repeated;
  }
  EXPECT_GT(repeats, 100);  // about half of 288
  EXPECT_LT(repeats, 190);
}

TEST(DeviceInputTest, ASeatedUserStaysWhereTheClipStartsLowerAndAtADeskOverIt) {
  // A walk: the pelvis (1 m above the ankles at 0.1 m) travels 1 m/s along z; the left hand swings
  // from 0.2 m to 1.0 m high, the right one reaches for the floor.
  LandmarkTruth truth{.frame_time = 1.0 / 30.0, .positions = {}};
  for (int f = 0; f <= 60; ++f) {
    const float z = f / 30.0f, swing = 0.6f + 0.4f * std::sin(f / 5.0f);
    std::array<Eigen::Vector3f, kNumScoredLandmarks> frame;
    frame.fill(Eigen::Vector3f(0.0f, 1.0f, z));
    frame[kLeftAnkleLandmark] = frame[kRightAnkleLandmark] = Eigen::Vector3f(0.0f, 0.1f, z);
    frame[kPelvisLandmark] = Eigen::Vector3f(0.0f, 1.1f, z);
    frame[kLeftWristLandmark] = Eigen::Vector3f(0.3f, swing, z + 0.1f);
    frame[kRightWristLandmark] = Eigen::Vector3f(-0.3f, 0.15f, z);
    truth.positions.push_back(frame);
  }
  auto device = [](Posture posture) {
    DeviceModel d{.name = "posture", .rate_hz = 30, .posture = posture};
    EXPECT_EQ(d.accuracy_measured(), posture == Posture::kAsCaptured);
    return d;
  };
  const auto standing = DeviceSamples(truth, device(Posture::kAsCaptured), 0.0, 1);
  const auto seated = DeviceSamples(truth, device(Posture::kSeated), 0.0, 1);
  const auto desk = DeviceSamples(truth, device(Posture::kAtADesk), 0.0, 1);
  ASSERT_EQ(seated.size(), standing.size());
  ASSERT_EQ(desk.size(), standing.size());
  for (size_t i = 0; i < seated.size(); ++i) {
    EXPECT_NEAR(standing[i].left.z(), standing[i].time + 0.1, 1e-5);
    EXPECT_NEAR(seated[i].left.z(), 0.1f, 1e-5) << "no travel";
    EXPECT_NEAR(seated[i].left.x(), 0.3f, 1e-5);
    EXPECT_NEAR(seated[i].left.y(), std::max(standing[i].left.y() - 0.5f, 0.1f), 1e-5) << "half the leg lower";
    EXPECT_NEAR(seated[i].right.y(), 0.1f, 1e-5) << "no lower than the floor's ankles";
    EXPECT_NEAR(desk[i].left.y(), std::max(seated[i].left.y(), 0.85f), 1e-5) << "over a desk at 3/4 of the leg";
    EXPECT_NEAR(desk[i].right.y(), 0.85f, 1e-5);
  }
}

TEST(DeviceInputTest, DropoutsLeaveGapsAndPhonesDrift) {
  DeviceModel dropouts = StandardDevices()[3];
  ASSERT_EQ(dropouts.name, "dropouts");
  dropouts.gap_every_s = 1.0;  // several in 4 s
  const auto samples = DeviceSamples(MovingWrists(), dropouts, 0.0, 3);
  double longest = 0;
  for (size_t i = 1; i < samples.size(); ++i) {
    EXPECT_GT(samples[i].time, samples[i - 1].time);
    longest = std::max(longest, samples[i].time - samples[i - 1].time);
  }
  EXPECT_GE(longest, 0.1);
  EXPECT_LE(longest, 2.0 + 1.0 / 60);
  DeviceModel drift{.name = "drift", .rate_hz = 60, .drift_m_per_sqrt_s = 0.05};
  const auto drifting = DeviceSamples(MovingWrists(), drift, 0.0, 5);
  EXPECT_NEAR((drifting[1].right - Eigen::Vector3f(-0.2f, 1.1f, 0.3f)).norm(), 0.0, 0.03);  // small at first
  double far = 0;
  for (const auto& s : drifting) far = std::max(far, double((s.right - Eigen::Vector3f(-0.2f, 1.1f, 0.3f)).norm()));
  EXPECT_GT(far, 0.02);  // and wanders
  EXPECT_LT(far, 0.5);
}

}  // namespace
}  // namespace mocap::eval

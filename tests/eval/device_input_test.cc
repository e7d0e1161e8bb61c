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

#include "motion/reconstruct/hand_rest.h"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>

namespace mocap {
namespace {

constexpr double kRate = 30.0;

// A hand held still to `jitter` metres while the other hand moves at `other_speed` m/s: the time
// of the first frame said put down, if any, within `seconds`.
std::optional<double> FirstPutDown(float jitter, float other_speed, double seconds = 6.0) {
  HandRestDetector detector;
  for (int f = 0; f < static_cast<int>(seconds * kRate); ++f) {
    const double t = f / kRate;
    const Eigen::Vector3f hand(0.5f + jitter * static_cast<float>(std::sin(7.0 * t)), 0.8f, 0.0f);
    const Eigen::Vector3f other(-0.3f, 0.8f, other_speed * static_cast<float>(t));
    if (detector.Update(t, hand, other)) return t;
  }
  return std::nullopt;
}

TEST(HandRestDetectorTest, AStillDeviceWhileTheOtherHandMovesIsPutDownWithinThreeSeconds) {
  const std::optional<double> at = FirstPutDown(0.003f, 0.5f);
  ASSERT_TRUE(at);
  EXPECT_GE(*at, kPutDownSeconds);
  EXPECT_LE(*at, 3.0);
}

TEST(HandRestDetectorTest, AHeldHandOrAPersonAtRestIsNot) {
  EXPECT_FALSE(FirstPutDown(0.03f, 0.5f));   // a held hand moves by centimetres
  EXPECT_FALSE(FirstPutDown(0.003f, 0.0f));  // both still: at rest, or both devices down
}

TEST(HandRestDetectorTest, PickedUpOnceItLeavesItsPlace) {
  HandRestDetector detector;
  bool put_down = false;
  double t = 0.0;
  for (; t < 3.5; t += 1.0 / kRate) put_down = detector.Update(t, {0.5f, 0.8f, 0.0f}, {0.0f, 0.8f, float(t)});
  ASSERT_TRUE(put_down);
  EXPECT_TRUE(detector.Update(t, {0.52f, 0.8f, 0.0f}, {0.0f, 0.8f, float(t)}));  // 2 cm: still there
  EXPECT_FALSE(detector.Update(t + 0.03, {0.6f, 0.8f, 0.0f}, {0.0f, 0.8f, float(t)}));
}

}  // namespace
}  // namespace mocap

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

// Frames where a hand is a guess are no evidence: a still run across them starts again, and a
// device already put down stays so while its tracker briefly loses it.
TEST(HandRestDetectorTest, GuessedFramesAreNoEvidence) {
  HandRestDetector detector;
  const Eigen::Vector3f still(0.5f, 0.8f, 0.0f);
  auto other = [](double t) { return Eigen::Vector3f(0.0f, 0.8f, static_cast<float>(t)); };
  double t = 0.0;
  for (; t < 2.0; t += 1.0 / kRate) ASSERT_FALSE(detector.Update(t, still, other(t)));
  for (; t < 3.0; t += 1.0 / kRate) ASSERT_FALSE(detector.Unobserved());
  double first = -1.0;
  for (; t < 6.0 && first < 0; t += 1.0 / kRate) {
    if (detector.Update(t, still, other(t))) first = t;
  }
  ASSERT_GE(first, 0.0);
  EXPECT_GE(first, 3.0 + kPutDownSeconds - 1e-6) << "the still run counts from the first observed frame";
  for (int f = 0; f < 30; ++f) EXPECT_TRUE(detector.Unobserved());
  EXPECT_TRUE(detector.Update(t + 1.0, still, other(t + 1.0)));  // found where it was
}

// Once put down, the detector says how far the other hand went over the ground while this one
// lay still: the person's walk the session lets the let-go hand catch up with.
TEST(HandRestDetectorTest, TellsHowFarTheOtherHandWentWhileItLayStill) {
  HandRestDetector detector;
  double t = 0.0;
  bool put_down = false;
  auto other = [](double time) { return Eigen::Vector3f(0.0f, 0.8f + 0.1f * float(time), 1.2f * float(time)); };
  for (; !put_down && t < 5.0; t += 1.0 / kRate) put_down = detector.Update(t, {0.5f, 0.8f, 0.0f}, other(t));
  ASSERT_TRUE(put_down);
  const Eigen::Vector3f travel = detector.other_travel_since_set_down();
  EXPECT_NEAR(travel.z(), 1.2f * kPutDownSeconds, 0.05f);
  EXPECT_EQ(travel.y(), 0.0f) << "over the ground: a hand that rose did not take the body up";
  EXPECT_NEAR(travel.x(), 0.0f, 1e-6f);
}

// A hand resting at the side while the other one waves in place is still too; wrists alone cannot
// tell it from a device on a table beside the person, so only a device the person left is told.
TEST(HandRestDetectorTest, AHandAtRestWhileTheOtherWavesIsNot) {
  HandRestDetector detector(/*wrist_span=*/1.4f);
  for (double t = 0.0; t < 10.0; t += 1.0 / kRate) {
    const Eigen::Vector3f wave(0.3f + 0.25f * static_cast<float>(std::cos(6.0 * t)),
                               1.5f + 0.2f * static_cast<float>(std::sin(6.0 * t)), 0.1f);
    ASSERT_FALSE(detector.Update(t, {-0.2f, 0.8f, 0.0f}, wave)) << "at " << t << " s";
  }
}

// A device the person walked away from lies where no arm holds it once the hands are further apart
// than the body's wrists reach: told then, sooner than kPutDownSeconds.
TEST(HandRestDetectorTest, ADeviceLeftBeyondTheArmsSpanIsToldSooner) {
  constexpr float kSpan = 1.4f;
  HandRestDetector detector(kSpan);
  std::optional<double> at;
  for (double t = 0.0; t < 5.0 && !at; t += 1.0 / kRate) {
    if (detector.Update(t, {0.2f, 0.8f, 0.0f}, {-0.2f, 0.8f, 1.2f * static_cast<float>(t)})) at = t;
  }
  ASSERT_TRUE(at);
  // The hands are kOutOfReachMargin × kSpan apart after 1.24 s of walking at 1.2 m/s.
  EXPECT_NEAR(*at, 1.24, 0.05);
  EXPECT_NEAR(detector.other_travel_since_set_down().z(), 1.2f * *at, 0.05f);
  // Without a span, the same walk waits for kPutDownSeconds.
  EXPECT_GE(FirstPutDown(0.0f, 1.2f).value_or(0.0), kPutDownSeconds);
}

}  // namespace
}  // namespace mocap

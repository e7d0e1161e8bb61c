#include "motion/reconstruct/one_hand_bridge.h"

#include <algorithm>
#include <limits>

#include <gtest/gtest.h>

namespace mocap {
namespace {

constexpr double kSamplePeriod = 1.0 / 60.0;
const Eigen::Vector3f kWalkingVelocity(1.2f, 0.0f, 0.0f);  // m/s along x

// Both hands carried along x at walking pace, the left swinging back and forth in z.
WristSample Walking(int i) {
  const float t = static_cast<float>(i * kSamplePeriod);
  return {.time = i * kSamplePeriod,
          .left = Eigen::Vector3f(0.0f, 1.0f, 0.2f) + t * kWalkingVelocity +
                  Eigen::Vector3f(0, 0, 0.1f * std::sin(6.0f * t)),
          .right = Eigen::Vector3f(0.0f, 1.0f, -0.2f) + t * kWalkingVelocity};
}

WristSample LeftLost(int i) {
  WristSample s = Walking(i);
  s.tracked[0] = false;
  s.left = Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN());  // not to be read
  return s;
}

TEST(OneHandBridgeTest, HandsBothTrackedPassThrough) {
  OneHandBridge bridge;
  for (int i = 0; i < 120; ++i) {
    WristSample s = Walking(i);
    std::array<float, 2> untracked{-1, -1};
    ASSERT_TRUE(bridge.Fill(&s, &untracked));
    EXPECT_EQ(s.left, Walking(i).left);
    EXPECT_EQ(s.right, Walking(i).right);
    EXPECT_EQ(untracked[0], 0.0f);
    EXPECT_EQ(untracked[1], 0.0f);
  }
}

TEST(OneHandBridgeTest, NothingToGoOnFromIsADropout) {
  OneHandBridge bridge;
  std::array<float, 2> untracked;
  WristSample lost = LeftLost(0);
  EXPECT_FALSE(bridge.Fill(&lost, &untracked));  // the left hand was never seen
  WristSample none = Walking(1);
  none.tracked = {false, false};
  EXPECT_FALSE(bridge.Fill(&none, &untracked));
  WristSample both = Walking(2);
  EXPECT_TRUE(bridge.Fill(&both, &untracked));
  none.time = 3 * kSamplePeriod;
  EXPECT_FALSE(bridge.Fill(&none, &untracked));  // both lost: the resampler's dropout, not this
}

TEST(OneHandBridgeTest, ALostHandTravelsWithTheBodyAndReturnsSmoothly) {
  OneHandBridge bridge(/*reentry_seconds=*/0.5, /*travel_seconds=*/1.0);
  std::array<float, 2> untracked;
  for (int i = 0; i < 120; ++i) {  // 2 s both tracked
    WristSample s = Walking(i);
    ASSERT_TRUE(bridge.Fill(&s, &untracked));
  }
  const Eigen::Vector3f last_seen = Walking(119).left;
  Eigen::Vector3f previous = last_seen;
  for (int i = 120; i < 180; ++i) {  // 1 s with the left hand lost
    WristSample s = LeftLost(i);
    ASSERT_TRUE(bridge.Fill(&s, &untracked));
    ASSERT_TRUE(s.left.allFinite());
    EXPECT_EQ(s.right, Walking(i).right);  // the tracked hand is the input
    EXPECT_NEAR(untracked[0], (i - 119) * kSamplePeriod, 1e-6);
    EXPECT_EQ(untracked[1], 0.0f);
    // Carried at the walking pace (the right hand's mean velocity), not swinging.
    EXPECT_NEAR((s.left - previous).x(), kWalkingVelocity.x() * kSamplePeriod, 1e-4) << i;
    EXPECT_NEAR((s.left - previous).z(), 0.0f, 1e-5) << i;
    previous = s.left;
  }
  EXPECT_NEAR((previous - last_seen).x(), kWalkingVelocity.x() * 60 * kSamplePeriod, 1e-3);
  // Back: the first sample is where the guess was going, then it eases onto the input.
  float largest_step = 0.0f;
  for (int i = 180; i < 240; ++i) {
    WristSample s = Walking(i);
    ASSERT_TRUE(bridge.Fill(&s, &untracked));
    EXPECT_EQ(untracked[0], 0.0f);
    largest_step = std::max(largest_step, (s.left - previous).norm());
    previous = s.left;
    if (i >= 180 + 30) {
      EXPECT_EQ(s.left, Walking(i).left) << "eased in within 0.5 s";
    }
  }
  // No jump at re-entry: steps no larger than the walk's plus the swing's plus the eased share of
  // the (up to 10 cm) difference.
  EXPECT_LT(largest_step, (kWalkingVelocity.x() + 0.6f) * kSamplePeriod + 1.5f * 0.1f / 30.0f);
}

// While a returning hand eases onto its input, the bridge says how much of it is still the guess
// (the confidence's "recently untracked" cue): all of it at re-entry, falling to none by the end
// of the fade, with the seconds since the hand was last tracked; nothing for the other hand.
TEST(OneHandBridgeTest, AReturningHandReportsTheGuessStillInIt) {
  OneHandBridge bridge(/*reentry_seconds=*/0.5, /*travel_seconds=*/1.0);
  std::array<float, 2> untracked;
  std::array<FadingGuess, 2> fading;
  for (int i = 0; i < 120; ++i) {
    WristSample s = Walking(i);
    ASSERT_TRUE(bridge.Fill(&s, &untracked, &fading));
    EXPECT_EQ(fading[0].weight, 0.0f);
  }
  for (int i = 120; i < 180; ++i) {  // lost: untracked, not fading
    WristSample s = LeftLost(i);
    ASSERT_TRUE(bridge.Fill(&s, &untracked, &fading));
    EXPECT_EQ(fading[0].weight, 0.0f);
    EXPECT_GT(untracked[0], 0.0f);
  }
  float previous_weight = 1.0f;
  for (int i = 180; i < 240; ++i) {
    WristSample s = Walking(i);
    ASSERT_TRUE(bridge.Fill(&s, &untracked, &fading));
    EXPECT_EQ(untracked[0], 0.0f) << "its input is real again";
    EXPECT_EQ(fading[1].weight, 0.0f);
    if (i == 180) {
      EXPECT_EQ(fading[0].weight, 1.0f) << "all guess at re-entry";
    }
    EXPECT_LE(fading[0].weight, previous_weight) << i;
    if (fading[0].weight > 0) {
      EXPECT_NEAR(fading[0].seconds, (i - 119) * kSamplePeriod, 1e-5) << i;
      // The share of the guess in the position is exactly the reported weight.
      const WristSample guess_free = Walking(i);
      const float input_gap = (s.left - guess_free.left).norm();
      EXPECT_LE(input_gap, fading[0].weight * 0.5f + 1e-5f) << i;
    }
    if (i >= 180 + 30) {
      EXPECT_EQ(fading[0].weight, 0.0f) << "eased in within 0.5 s";
    }
    previous_weight = fading[0].weight;
  }
}

TEST(OneHandBridgeTest, AStandingBodyKeepsTheLostHandInPlace) {
  OneHandBridge bridge;
  std::array<float, 2> untracked;
  auto standing = [](int i) {
    const float t = static_cast<float>(i * kSamplePeriod);
    return WristSample{.time = i * kSamplePeriod,
                       .left = Eigen::Vector3f(0.2f, 1.0f, 0.0f),
                       .right = Eigen::Vector3f(-0.2f, 1.2f + 0.15f * std::sin(4.0f * t), 0.2f)};  // waving
  };
  for (int i = 0; i < 120; ++i) {
    WristSample s = standing(i);
    ASSERT_TRUE(bridge.Fill(&s, &untracked));
  }
  for (int i = 120; i < 300; ++i) {
    WristSample s = standing(i);
    s.tracked[0] = false;
    ASSERT_TRUE(bridge.Fill(&s, &untracked));
    EXPECT_LT((s.left - standing(119).left).norm(), 0.15f) << "it does not wave along";
  }
}

// Raising the tracked hand does not lift the lost one: a body travels over the ground, a hand
// that rises gestures (a lost hand that copied it left the body reaching up for it).
TEST(OneHandBridgeTest, ALostHandDoesNotRiseWithTheTrackedOne) {
  OneHandBridge bridge;
  std::array<float, 2> untracked;
  auto standing = [](int i) {
    return WristSample{.time = i * kSamplePeriod,
                       .left = Eigen::Vector3f(0.0f, 1.0f, 0.2f),
                       .right = Eigen::Vector3f(0.0f, 1.0f + 0.8f * static_cast<float>(i * kSamplePeriod), -0.2f)};
  };
  for (int i = 0; i < 60; ++i) {
    WristSample s = standing(i);
    ASSERT_TRUE(bridge.Fill(&s, &untracked));
  }
  for (int i = 60; i < 120; ++i) {  // the right hand goes on rising at 0.8 m/s, the left is lost
    WristSample s = standing(i);
    s.tracked[0] = false;
    ASSERT_TRUE(bridge.Fill(&s, &untracked));
    EXPECT_LT((s.left - Eigen::Vector3f(0.0f, 1.0f, 0.2f)).norm(), 1e-4f) << i;
  }
}

// A hand let go late (a device found put down while its person walked on) is carried by an offset
// as well, eased in over kCatchUpSeconds: in the end the whole offset, and no step on the way.
TEST(OneHandBridgeTest, ACarriedOffsetIsEasedInWithoutAStep) {
  OneHandBridge bridge;
  std::array<float, 2> untracked;
  for (int i = 0; i < 60; ++i) {  // 1 s both tracked
    WristSample s = Walking(i);
    ASSERT_TRUE(bridge.Fill(&s, &untracked));
  }
  const Eigen::Vector3f offset(2.0f, 0.0f, 0.5f);
  bridge.Carry(0, offset);
  Eigen::Vector3f previous = Walking(59).left;
  float largest_step = 0.0f;
  const int catch_up_samples = static_cast<int>(OneHandBridge::kCatchUpSeconds / kSamplePeriod);
  for (int i = 60; i < 60 + 2 * catch_up_samples; ++i) {
    WristSample s = LeftLost(i);
    ASSERT_TRUE(bridge.Fill(&s, &untracked));
    // What the body's pace carries it each sample, besides the offset's share.
    largest_step = std::max(largest_step, (s.left - previous - kSamplePeriod * kWalkingVelocity).norm());
    previous = s.left;
  }
  const Eigen::Vector3f without_offset =
      Walking(59).left + static_cast<float>(2 * catch_up_samples) * kSamplePeriod * kWalkingVelocity;
  EXPECT_LT((previous - without_offset - offset).norm(), 0.01f);
  // Smoothstep's steepest share is 1.5 / catch-up samples of the offset; a step would be all of it.
  EXPECT_LT(largest_step, 1.6f * offset.norm() / static_cast<float>(catch_up_samples));
}

// An offset still to come when the hand is its own input again is dropped, not saved for the
// hand's next loss.
TEST(OneHandBridgeTest, ACarriedOffsetEndsWithTheGuess) {
  OneHandBridge bridge(/*reentry_seconds=*/0.5, /*travel_seconds=*/1.0);
  std::array<float, 2> untracked;
  int i = 0;
  for (; i < 60; ++i) {
    WristSample s = Walking(i);
    ASSERT_TRUE(bridge.Fill(&s, &untracked));
  }
  bridge.Carry(0, Eigen::Vector3f(3.0f, 0.0f, 0.0f));
  WristSample lost = LeftLost(i++);
  ASSERT_TRUE(bridge.Fill(&lost, &untracked));
  for (; i < 120; ++i) {  // back at once, and tracked past its cross-fade
    WristSample s = Walking(i);
    ASSERT_TRUE(bridge.Fill(&s, &untracked));
  }
  Eigen::Vector3f previous = lost.left;
  for (int lost_again = 0; lost_again < 30; ++lost_again, ++i) {
    WristSample s = LeftLost(i);
    ASSERT_TRUE(bridge.Fill(&s, &untracked));
    if (lost_again > 0) {
      EXPECT_LT((s.left - previous).norm(), 0.05f) << "sample " << lost_again;
    }
    previous = s.left;
  }
}

}  // namespace
}  // namespace mocap

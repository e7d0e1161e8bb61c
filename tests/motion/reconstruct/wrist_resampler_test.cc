#include "motion/reconstruct/wrist_resampler.h"

#include <limits>

#include <gtest/gtest.h>

namespace mocap {
namespace {

WristSample At(double t) {
  // Wrists moving linearly: interpolation must be exact.
  return {t, Eigen::Vector3f(static_cast<float>(t), 1.0f, 0.0f),
          Eigen::Vector3f(-static_cast<float>(t), 1.0f, 2.0f * static_cast<float>(t))};
}

TEST(WristResamplerTest, AnyInputRateLandsOnTheDatabaseGrid) {
  for (double rate : {30.0, 60.0, 90.0, 24.0, 7.0}) {
    WristResampler resampler(1.0 / 30.0, 0.25);
    std::vector<GridSample> out;
    for (int i = 0; i <= static_cast<int>(rate); ++i) ASSERT_TRUE(resampler.Push(At(5.0 + i / rate), &out).ok());
    ASSERT_EQ(out.size(), 31u) << rate;  // 5 s .. 6 s at 30 Hz
    for (size_t k = 0; k < out.size(); ++k) {
      EXPECT_NEAR(out[k].time, 5.0 + k / 30.0, 1e-9);
      EXPECT_NEAR(out[k].left.x(), out[k].time, 1e-5);
      EXPECT_NEAR(out[k].right.z(), 2 * out[k].time, 1e-5);
      EXPECT_EQ(out[k].starts_segment, k == 0);
    }
  }
}

TEST(WristResamplerTest, ATrackerAtTheNominalRateGivesOneFramePerSample) {
  // A BVH's "Frame Time: 0.033333" (float) against a database at 1/30 s: 280 samples drift by
  // about 1e-4 s, and must still give 280 frames, in the slower and the faster direction.
  for (double period : {static_cast<double>(0.033333f), 1.0 / 29.9997}) {
    WristResampler resampler(1.0 / 30.0, 0.25);
    std::vector<GridSample> out;
    for (int i = 0; i < 280; ++i) ASSERT_TRUE(resampler.Push(At(i * period), &out).ok());
    EXPECT_EQ(out.size(), 280u) << period;
  }
}

TEST(WristResamplerTest, ShortDropoutsAreBridgedLongOnesStartANewSegment) {
  WristResampler resampler(1.0 / 30.0, 0.25);
  std::vector<GridSample> out;
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(resampler.Push(At(i / 30.0), &out).ok());
  ASSERT_TRUE(resampler.Push(At(15 / 30.0), &out).ok());  // 5 frames missing: bridged
  ASSERT_EQ(out.size(), 16u);
  EXPECT_TRUE(out[12].bridged);
  EXPECT_FALSE(out[12].starts_segment);
  EXPECT_FALSE(out[15].bridged);  // the sample after the dropout is input again
  EXPECT_NEAR(out[12].left.x(), 12 / 30.0, 1e-5);
  ASSERT_TRUE(resampler.Push(At(2.0), &out).ok());  // 1.5 s gap: a new segment
  ASSERT_EQ(out.size(), 17u);
  EXPECT_TRUE(out.back().starts_segment);
  EXPECT_DOUBLE_EQ(out.back().time, 2.0);
}

TEST(WristResamplerTest, SaysHowLongEachHandsInputHasNotBeenReal) {
  WristResampler resampler(1.0 / 30.0, 1.0);
  std::vector<GridSample> out;
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(resampler.Push(At(i / 30.0), &out).ok());
  ASSERT_TRUE(resampler.Push(At(19 / 30.0), &out).ok());  // 9 frames missing: bridged
  ASSERT_EQ(out.size(), 20u);
  for (int k = 10; k < 19; ++k) {  // the seconds to the nearer real sample, both hands
    const float expected = static_cast<float>(std::min(k - 9, 19 - k) / 30.0);
    EXPECT_NEAR(out[k].untracked_seconds[0], expected, 1e-6) << k;
    EXPECT_NEAR(out[k].untracked_seconds[1], expected, 1e-6) << k;
  }
  EXPECT_EQ(out[19].untracked_seconds[0], 0.0f);
  // A hand held by the other (OneHandBridge) brings its own seconds, interpolated onto the grid.
  ASSERT_TRUE(resampler.Push(At(20.5 / 30.0), &out, {0.0f, 0.5f}).ok());
  ASSERT_EQ(out.size(), 21u);
  EXPECT_NEAR(out[20].untracked_seconds[1], 0.5f * (1.0f / 1.5f), 1e-5);
  EXPECT_EQ(out[20].untracked_seconds[0], 0.0f);
}

TEST(WristResamplerTest, RefusesNonFiniteSamplesAndTimeGoingBackwardsAndCarriesOn) {
  WristResampler resampler(1.0 / 30.0, 0.25);
  std::vector<GridSample> out;
  ASSERT_TRUE(resampler.Push(At(0.0), &out).ok());
  WristSample nan = At(1 / 30.0);
  nan.right.y() = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(resampler.Push(nan, &out).code(), absl::StatusCode::kInvalidArgument);
  WristSample inf = At(1 / 30.0);
  inf.left.x() = std::numeric_limits<float>::infinity();
  EXPECT_EQ(resampler.Push(inf, &out).code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(resampler.Push(At(-1.0), &out).code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(resampler.Push(At(0.0), &out).code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(resampler.Push(At(std::numeric_limits<double>::quiet_NaN()), &out).code(),
            absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(out.size(), 1u);
  ASSERT_TRUE(resampler.Push(At(1 / 30.0), &out).ok());
  EXPECT_EQ(out.size(), 2u);
}

TEST(WristResamplerTest, ATrackerRepeatingItsLastPositionIsNotReadAsAStopAndACatchUp) {
  // Controllers at 72 Hz that did not update for one to three samples: the same positions again
  // with new times. The grid must follow the hands' real (linear) path, frame for frame.
  for (int hand = 0; hand < 3; ++hand) {  // left repeats, right repeats, both repeat
    WristResampler resampler(1.0 / 30.0, 0.25);
    std::vector<GridSample> out;
    WristSample last = At(0.0);
    for (int i = 0; i <= 144; ++i) {  // 2 s
      WristSample sample = At(i / 72.0);
      if (i % 4 != 0 && i < 140) {  // three repeats of every fourth sample: 42 ms
        if (hand != 1) sample.left = last.left;
        if (hand != 0) sample.right = last.right;
      }
      last = sample;
      ASSERT_TRUE(resampler.Push(sample, &out).ok());
    }
    ASSERT_EQ(out.size(), 61u) << hand;                                   // the last sample is new: nothing waits
    EXPECT_EQ(resampler.repeated_hand_samples(), hand == 2 ? 210 : 105);  // 1..139 but every fourth
    for (size_t k = 0; k < out.size(); ++k) {
      EXPECT_NEAR(out[k].time, k / 30.0, 1e-9);
      EXPECT_NEAR(out[k].left.x(), out[k].time, 1e-5) << hand << " " << k;
      EXPECT_NEAR(out[k].right.z(), 2 * out[k].time, 1e-5) << hand << " " << k;
    }
  }
}

TEST(WristResamplerTest, AStillHandOnAQuantisedTrackerWaitsNoLongerThanTheHold) {
  // A hand that does not move repeats itself for as long as it is still: a repeat later than
  // kRepeatHoldSeconds after the hand's last new position is input, so frames keep coming.
  WristResampler resampler(1.0 / 30.0, 0.25);
  std::vector<GridSample> out;
  const Eigen::Vector3f still(0.3f, 1.0f, 0.2f);
  for (int i = 0; i <= 90; ++i) {
    const double t = i / 90.0;
    ASSERT_TRUE(resampler.Push({t, still, Eigen::Vector3f(static_cast<float>(t), 1.0f, 0.0f)}, &out).ok());
    ASSERT_FALSE(out.empty());
    EXPECT_GE(out.back().time, t - WristResampler::kRepeatHoldSeconds - 1.0 / 30.0 - 1e-9) << i;
    for (const GridSample& g : out) EXPECT_LT((g.left - still).norm(), 1e-6f);
  }
  resampler.Flush(&out);
  ASSERT_EQ(out.size(), 31u);
  EXPECT_NEAR(out.back().right.x(), 1.0f, 1e-5);
}

TEST(WristResamplerTest, WhatWaitsForARepeatingHandIsHeldAtTheEndOfTheInputAndBeforeANewSegment) {
  WristResampler resampler(1.0 / 30.0, 0.25);
  std::vector<GridSample> out;
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(resampler.Push(At(i / 30.0), &out).ok());
  WristSample repeat = At(10 / 30.0);
  repeat.left = out.back().left;  // the left tracker did not update
  ASSERT_TRUE(resampler.Push(repeat, &out).ok());
  EXPECT_EQ(out.size(), 10u);                       // frame 10 waits for the left hand's next position
  ASSERT_TRUE(resampler.Push(At(1.0), &out).ok());  // 0.63 s later: a new segment
  ASSERT_EQ(out.size(), 12u);
  EXPECT_FALSE(out[10].starts_segment);
  EXPECT_FLOAT_EQ(out[10].left.x(), 9 / 30.0f);  // held where it was last seen
  EXPECT_NEAR(out[10].right.z(), 20 / 30.0f, 1e-5);
  EXPECT_TRUE(out[11].starts_segment);
  repeat = At(31 / 30.0);
  repeat.right = out.back().right;
  ASSERT_TRUE(resampler.Push(repeat, &out).ok());
  EXPECT_EQ(out.size(), 12u);
  resampler.Flush(&out);
  ASSERT_EQ(out.size(), 13u);
  EXPECT_NEAR(out.back().left.x(), 31 / 30.0f, 1e-5);
  EXPECT_FLOAT_EQ(out.back().right.z(), 2.0f);
  resampler.Flush(&out);  // nothing twice
  EXPECT_EQ(out.size(), 13u);
}

TEST(WristResamplerTest, AHandHeldByTheOtherIsNoRepeat) {
  // OneHandBridge may hold a lost hand still: its positions are the bridge's, not a tracker's
  // repeat, and must not wait.
  WristResampler resampler(1.0 / 30.0, 0.25);
  std::vector<GridSample> out;
  const Eigen::Vector3f held(0.1f, 1.2f, 0.0f);
  for (int i = 0; i < 5; ++i) {
    WristSample s = At(i / 30.0);
    s.left = held;
    ASSERT_TRUE(resampler.Push(s, &out, {0.1f * static_cast<float>(i), 0.0f}).ok());
    EXPECT_EQ(out.size(), static_cast<size_t>(i + 1));
  }
}

}  // namespace
}  // namespace mocap

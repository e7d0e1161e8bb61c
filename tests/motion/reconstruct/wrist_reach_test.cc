// The performer's size from the wrists' reach (motion/reconstruct/wrist_reach.h): a database's
// reach is the farthest its wrists went; input within it keeps the database's size whatever it
// does, input that spends a twentieth of its time beyond it is told the ratio, a moment's stretch
// or a tracker's outlier is not, a lost hand does not count, and bad input is refused.
#include "motion/reconstruct/wrist_reach.h"

#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "tests/support/synthetic_database.h"

namespace mocap {
namespace {

// `seconds` of input at 60 Hz: hands `apart` metres apart at `height`, swinging a little.
std::vector<WristSample> Held(float apart, float height, double seconds = 3.0) {
  std::vector<WristSample> samples;
  for (int i = 0; i < static_cast<int>(seconds * 60); ++i) {
    const float swing = 0.02f * std::sin(0.3f * static_cast<float>(i));
    samples.push_back({.time = i / 60.0,
                       .left = Eigen::Vector3f(0.5f * apart, height + swing, 0.1f),
                       .right = Eigen::Vector3f(-0.5f * apart, height - swing, 0.1f)});
  }
  return samples;
}

constexpr WristReach kDatabase{.separation = 1.2f, .height = 1.9f};

TEST(WristReachTest, ADatabasesReachIsTheFarthestItsWristsWent) {
  const auto setup = testing::MakeSyntheticReconstructionSetup({}, 90);
  const WristReach reach = setup.database->wrist_reach();
  ASSERT_GT(reach.separation, 0.0f);
  ASSERT_GT(reach.height, 0.0f);
  // Its own input never reaches beyond it: the database's size.
  const absl::StatusOr<ReachScale> own = InputScaleFromReach(reach, testing::WristSamplesOf(setup));
  ASSERT_TRUE(own.ok()) << own.status();
  EXPECT_EQ(own->input_scale, 1.0f);
  EXPECT_LE(own->separation, reach.separation);
  EXPECT_LE(own->height, reach.height);
}

TEST(WristReachTest, InputWithinTheDatabasesReachKeepsItsSize) {
  for (auto [apart, height] : {std::pair{0.3f, 0.9f}, std::pair{1.1f, 1.4f}, std::pair{0.5f, 1.85f}}) {
    const absl::StatusOr<ReachScale> scale = InputScaleFromReach(kDatabase, Held(apart, height));
    ASSERT_TRUE(scale.ok()) << scale.status();
    EXPECT_EQ(scale->input_scale, 1.0f) << apart << " m apart at " << height << " m";
  }
}

TEST(WristReachTest, WristsHeldFartherApartOrHigherTellTheRatio) {
  const absl::StatusOr<ReachScale> apart = InputScaleFromReach(kDatabase, Held(1.5f, 1.4f));
  ASSERT_TRUE(apart.ok()) << apart.status();
  EXPECT_NEAR(apart->input_scale, 1.2f / 1.5f, 0.01f);
  const absl::StatusOr<ReachScale> high = InputScaleFromReach(kDatabase, Held(0.4f, 2.3f));
  ASSERT_TRUE(high.ok()) << high.status();
  EXPECT_NEAR(high->input_scale, 1.9f / 2.32f, 0.01f);  // the higher hand, at the top of its swing
  // Both beyond: the larger ratio decides, and a giant is held to min_scale.
  const absl::StatusOr<ReachScale> giant = InputScaleFromReach(kDatabase, Held(3.0f, 4.0f));
  ASSERT_TRUE(giant.ok()) << giant.status();
  EXPECT_FLOAT_EQ(giant->input_scale, ReachScaleOptions{}.min_scale);
}

TEST(WristReachTest, AMomentsStretchOrAnOutlierIsNoEvidence) {
  std::vector<WristSample> samples = Held(0.5f, 1.2f);          // 180 samples
  for (int i = 0; i < 6; ++i) samples[40 + i].left.x() = 2.0f;  // 0.1 s arms out, 3% of the input
  samples[100].right.y() = 5.0f;                                // a tracker's outlier
  const absl::StatusOr<ReachScale> scale = InputScaleFromReach(kDatabase, samples);
  ASSERT_TRUE(scale.ok()) << scale.status();
  EXPECT_EQ(scale->input_scale, 1.0f);
  // Held out for a fifth of the input, it is evidence.
  for (int i = 0; i < 36; ++i) samples[40 + i].left.x() = 1.5f;
  const absl::StatusOr<ReachScale> held = InputScaleFromReach(kDatabase, samples);
  ASSERT_TRUE(held.ok()) << held.status();
  EXPECT_LT(held->input_scale, 1.0f);
}

TEST(WristReachTest, ALostHandAndAShortInputSayNothing) {
  std::vector<WristSample> samples = Held(1.5f, 1.4f);
  for (WristSample& s : samples) {
    s.tracked[1] = false;  // the right hand lost: its position is whatever the tracker left
    s.right = Eigen::Vector3f(-3.0f, 3.0f, 0.0f);
  }
  const absl::StatusOr<ReachScale> one_hand = InputScaleFromReach(kDatabase, samples);
  ASSERT_TRUE(one_hand.ok()) << one_hand.status();
  EXPECT_EQ(one_hand->input_scale, 1.0f);  // no separation without both hands; the left's height is within
  const absl::StatusOr<ReachScale> short_input = InputScaleFromReach(kDatabase, Held(1.5f, 1.4f, 0.5));
  ASSERT_TRUE(short_input.ok()) << short_input.status();
  EXPECT_EQ(short_input->input_scale, 1.0f);
  EXPECT_TRUE(InputScaleFromReach(kDatabase, {}).ok());
}

TEST(WristReachTest, NonFiniteInputOrAnEmptyDatabaseIsRefused) {
  std::vector<WristSample> samples = Held(0.5f, 1.2f);
  samples[10].left.y() = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(InputScaleFromReach(kDatabase, samples).status().code(), absl::StatusCode::kInvalidArgument);
  samples[10].tracked[0] = false;  // a lost hand's position is not read
  EXPECT_TRUE(InputScaleFromReach(kDatabase, samples).ok());
  EXPECT_EQ(InputScaleFromReach(WristReach{}, Held(0.5f, 1.2f)).status().code(), absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace mocap

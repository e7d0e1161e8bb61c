// The performer's size by database fit (motion/reconstruct/performer_scale.h): the input of a body
// the database knows, shrunk or grown, is told back at the factor that undoes it; a short input
// gives no estimate; bad options and non-finite samples are refused.
#include "motion/reconstruct/performer_scale.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "tests/support/synthetic_database.h"

namespace mocap {
namespace {

std::vector<WristSample> Scaled(std::vector<WristSample> samples, float factor) {
  for (WristSample& s : samples) {
    s.left *= factor;
    s.right *= factor;
  }
  return samples;
}

TEST(PerformerScaleTest, AShrunkOrGrownWalkIsToldBackAtTheFactorThatUndoesIt) {
  const auto setup = testing::MakeSyntheticReconstructionSetup({}, 90);
  const std::vector<WristSample> samples = testing::WristSamplesOf(setup);
  for (float size : {0.85f, 1.0f, 1.2f}) {
    const absl::StatusOr<PerformerScaleEstimate> fit = EstimatePerformerScale(*setup.database, Scaled(samples, size));
    ASSERT_TRUE(fit.ok()) << fit.status();
    EXPECT_GT(fit->frames, 20);
    ASSERT_EQ(fit->candidates.size(), fit->cost.size());
    // Within one step of the grid (31 steps over 0.7-1.45: ~2.5% a step) of 1 / size.
    EXPECT_NEAR(std::log(fit->scale), -std::log(size), 0.06) << "performer ×" << size;
  }
}

TEST(PerformerScaleTest, TooShortAnInputGivesNoEstimate) {
  const auto setup = testing::MakeSyntheticReconstructionSetup({}, 20);
  std::vector<WristSample> samples = testing::WristSamplesOf(setup);
  samples.resize(15);  // half a second
  const absl::StatusOr<PerformerScaleEstimate> fit = EstimatePerformerScale(*setup.database, Scaled(samples, 1.3f));
  ASSERT_TRUE(fit.ok()) << fit.status();
  EXPECT_EQ(fit->scale, 1.0f);
  EXPECT_EQ(fit->frames, 0);
}

TEST(PerformerScaleTest, RefusesBadOptionsAndNonFiniteSamples) {
  const auto setup = testing::MakeSyntheticReconstructionSetup({}, 40);
  std::vector<WristSample> samples = testing::WristSamplesOf(setup);
  PerformerScaleOptions bad;
  bad.min_scale = 0.0f;
  EXPECT_EQ(EstimatePerformerScale(*setup.database, samples, bad).status().code(), absl::StatusCode::kInvalidArgument);
  samples[5].left.x() = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(EstimatePerformerScale(*setup.database, samples).status().code(), absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace mocap

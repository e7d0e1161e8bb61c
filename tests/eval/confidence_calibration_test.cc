// Scoring the expected landmark errors (eval/confidence_calibration.h): rank correlations with
// ties, the reliability bins, and the pairs taken from a frame.
#include "eval/confidence_calibration.h"

#include <gtest/gtest.h>

namespace mocap::eval {
namespace {

ConfidenceSample Pair(float predicted, float actual, int landmark = 0) {
  return {.predicted = predicted, .actual = actual, .landmark = static_cast<std::uint8_t>(landmark)};
}

TEST(ConfidenceCalibrationTest, AnExactPredictionRanksAndBinsPerfectly) {
  std::vector<ConfidenceSample> samples;
  for (int i = 1; i <= 100; ++i) samples.push_back(Pair(0.01f * i, 0.01f * i, i % kNumBodyLandmarks));
  const ConfidenceSummary s = SummariseConfidence(samples, 10);
  EXPECT_EQ(s.samples, 100);
  EXPECT_NEAR(s.spearman, 1.0, 1e-9);
  EXPECT_NEAR(s.spearman_within_landmarks, 1.0, 1e-9);
  ASSERT_EQ(s.bins.size(), 10u);
  for (const ReliabilityBin& bin : s.bins) {
    EXPECT_EQ(bin.count, 10);
    EXPECT_NEAR(bin.actual, bin.predicted, 1e-6);
  }
  EXPECT_NEAR(s.worst_bin_ratio, 1.0, 1e-6);
}

TEST(ConfidenceCalibrationTest, AReversedOrderIsNegativeAndATwiceTooLowOneIsOffByTwo) {
  std::vector<ConfidenceSample> reversed, low;
  for (int i = 1; i <= 50; ++i) {
    reversed.push_back(Pair(0.01f * i, 0.01f * (51 - i)));
    low.push_back(Pair(0.005f * i, 0.01f * i));
  }
  EXPECT_NEAR(SummariseConfidence(reversed).spearman, -1.0, 1e-9);
  EXPECT_NEAR(SummariseConfidence(low).worst_bin_ratio, 2.0, 1e-5);
}

TEST(ConfidenceCalibrationTest, TiesShareTheirRankAndNothingGivesAnEmptySummary) {
  // A constant prediction says nothing: no correlation, one value per bin.
  std::vector<ConfidenceSample> constant;
  for (int i = 0; i < 20; ++i) constant.push_back(Pair(0.05f, 0.01f * i));
  EXPECT_NEAR(SummariseConfidence(constant).spearman, 0.0, 1e-9);
  const ConfidenceSummary none = SummariseConfidence({});
  EXPECT_EQ(none.samples, 0);
  EXPECT_TRUE(none.bins.empty());
}

TEST(ConfidenceCalibrationTest, AFramesPairsAreItsExpectedErrorsScaledAgainstTheDistances) {
  ReconstructedFrame frame;
  for (int k = 0; k < kNumBodyLandmarks; ++k) frame.landmark_error[k] = 0.01f * (k + 1);
  std::array<Eigen::Vector3f, kNumBodyLandmarks> output, truth;
  for (int k = 0; k < kNumBodyLandmarks; ++k) {
    output[k] = Eigen::Vector3f(0, 0, 0);
    truth[k] = Eigen::Vector3f(0.02f * k, 0, 0);
  }
  std::vector<ConfidenceSample> samples;
  AddConfidenceSamples(frame, 2.0f, output, truth, &samples);
  ASSERT_EQ(samples.size(), static_cast<size_t>(kNumBodyLandmarks));
  for (int k = 0; k < kNumBodyLandmarks; ++k) {
    EXPECT_EQ(samples[k].landmark, k);
    EXPECT_FLOAT_EQ(samples[k].predicted, 0.02f * (k + 1));
    EXPECT_FLOAT_EQ(samples[k].actual, 0.02f * k);
  }
  const ConfidenceSummary summary = SummariseConfidence(samples, 4);
  EXPECT_NE(ReliabilitySvg("t", summary).find("<svg"), std::string::npos);
  EXPECT_NE(ConfidenceMarkdown({{"run", &summary}}).find("| run | 14 |"), std::string::npos);
}

}  // namespace
}  // namespace mocap::eval

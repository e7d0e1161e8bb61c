// The expected landmark errors (motion/reconstruct/landmark_confidence.h): the session's mean log
// energy, the calibration's direction in each cue, and every reconstructed frame carrying them.
#include "motion/reconstruct/landmark_confidence.h"

#include <cmath>

#include <gtest/gtest.h>

#include "motion/reconstruct/reconstruction_session.h"
#include "tests/support/synthetic_database.h"

namespace mocap {
namespace {

TEST(SessionCostTest, MeansTheLogEnergyOverItsWindowThenForgetsAtThatRate) {
  SessionCost cost(/*frame_time=*/0.1, /*window_seconds=*/1.0);  // a window of 10 frames
  EXPECT_NEAR(cost.Add(1.0f), LogSolverCost(1.0f), 1e-6);
  float mean = 0;
  for (int i = 0; i < 9; ++i) mean = cost.Add(100.0f);
  // The plain mean of 1 × log(1) and 9 × log(100) over the first window.
  EXPECT_NEAR(mean, (LogSolverCost(1.0f) + 9 * LogSolverCost(100.0f)) / 10, 1e-4);
  // Then an exponential mean of a 10-frame time constant: 30 frames of a new level leave
  // (1 − 1/10)^30 ≈ 4% of the old difference.
  for (int i = 0; i < 30; ++i) mean = cost.Add(1.0f);
  const float start = (LogSolverCost(1.0f) + 9 * LogSolverCost(100.0f)) / 10;
  EXPECT_NEAR(mean - LogSolverCost(1.0f), std::pow(0.9f, 30.0f) * (start - LogSolverCost(1.0f)), 1e-3);
  EXPECT_TRUE(std::isfinite(cost.Add(0.0f)));
}

TEST(ExpectedLandmarkErrorsTest, GrowWithEveryCueAndTheWristsAreSurest) {
  const ConfidenceCues base{
      .distance = 0.05f, .wrist_fit = 0.005f, .solver_cost = 2.0f, .session_log_cost = LogSolverCost(2.0f)};
  const LandmarkErrors at_base = ExpectedLandmarkErrors(base);
  for (float ConfidenceCues::*cue : {&ConfidenceCues::distance, &ConfidenceCues::wrist_fit,
                                     &ConfidenceCues::solver_cost, &ConfidenceCues::session_log_cost}) {
    ConfidenceCues worse = base;
    worse.*cue += cue == &ConfidenceCues::session_log_cost ? 2.0f : 10 * (base.*cue);
    const LandmarkErrors at_worse = ExpectedLandmarkErrors(worse);
    for (int k = 0; k < kNumBodyLandmarks; ++k) EXPECT_GT(at_worse[k], at_base[k]) << kBodyLandmarkNames[k];
  }
  const int left_wrist = 6, right_wrist = 7;
  for (int k = 0; k < kNumBodyLandmarks; ++k) {
    EXPECT_GT(at_base[k], 0.0f);
    EXPECT_LT(at_base[k], 1.0f) << "metres, for an ordinary frame";
    if (k != left_wrist && k != right_wrist) {
      EXPECT_GT(at_base[k], at_base[left_wrist]) << kBodyLandmarkNames[k];
    }
  }
  // Cues of zero (a lookup without a solve) stay finite.
  for (float e : ExpectedLandmarkErrors({})) EXPECT_TRUE(std::isfinite(e));
}

TEST(ExpectedLandmarkErrorsTest, InputThatIsNotRealWidensThemTheLongerItLasts) {
  const ConfidenceCues tracked{
      .distance = 0.05f, .wrist_fit = 0.005f, .solver_cost = 2.0f, .session_log_cost = LogSolverCost(2.0f)};
  const LandmarkErrors at_tracked = ExpectedLandmarkErrors(tracked);
  const int left_elbow = 4, right_elbow = 5, left_wrist = 6, right_wrist = 7;
  ConfidenceCues left_lost = tracked;
  LandmarkErrors previous = at_tracked;
  for (float seconds : {0.1f, 0.5f, 2.0f, 5.0f}) {
    left_lost.untracked_seconds = {seconds, 0.0f};
    const LandmarkErrors at_lost = ExpectedLandmarkErrors(left_lost);
    EXPECT_GT(at_lost[left_wrist], 3 * at_tracked[left_wrist]) << seconds << " s: the hand is a guess";
    EXPECT_GT(at_lost[left_elbow], previous[left_elbow]) << seconds << " s";
    EXPECT_GT(at_lost[0], previous[0]) << seconds << " s: the pelvis too";
    // The tracked side keeps its own.
    EXPECT_EQ(at_lost[right_wrist], at_tracked[right_wrist]);
    EXPECT_EQ(at_lost[right_elbow], at_tracked[right_elbow]);
    previous = at_lost;
  }
  EXPECT_EQ(UntrackedSecondsFor(left_lost, left_wrist), 5.0f);
  EXPECT_EQ(UntrackedSecondsFor(left_lost, right_wrist), 0.0f);
  EXPECT_EQ(UntrackedSecondsFor(left_lost, 0), 5.0f);  // the body: the longer of the two
  // Either hand lost for as long: mirrored errors.
  ConfidenceCues right_lost = tracked;
  right_lost.untracked_seconds = {0.0f, 5.0f};
  EXPECT_FLOAT_EQ(ExpectedLandmarkErrors(right_lost)[right_wrist], previous[left_wrist]);
}

// A hand that came back but is still partly the guess (the re-entry cross-fade): its landmarks'
// errors fall from the guess's to the tracked ones with the guess's weight.
TEST(ExpectedLandmarkErrorsTest, AReturningHandIsTrustedAsItsGuessFades) {
  const ConfidenceCues tracked{
      .distance = 0.05f, .wrist_fit = 0.005f, .solver_cost = 2.0f, .session_log_cost = LogSolverCost(2.0f)};
  const LandmarkErrors at_tracked = ExpectedLandmarkErrors(tracked);
  ConfidenceCues lost = tracked;
  lost.untracked_seconds = {2.0f, 0.0f};
  const LandmarkErrors at_lost = ExpectedLandmarkErrors(lost);
  const int left_wrist = 6, right_wrist = 7;
  ConfidenceCues fading = tracked;
  float previous = at_lost[left_wrist] * 1.0001f;
  for (float weight : {1.0f, 0.75f, 0.5f, 0.25f, 0.0f}) {
    fading.fading_guess = {FadingGuess{.weight = weight, .seconds = 2.0f}, FadingGuess{}};
    const LandmarkErrors errors = ExpectedLandmarkErrors(fading);
    EXPECT_LE(errors[left_wrist], previous) << weight;
    EXPECT_GE(errors[left_wrist], at_tracked[left_wrist]) << weight;
    EXPECT_EQ(errors[right_wrist], at_tracked[right_wrist]) << "the other hand is its own";
    if (weight == 1.0f) {
      EXPECT_FLOAT_EQ(errors[left_wrist], at_lost[left_wrist]);
    } else if (weight == 0.5f) {
      EXPECT_GT(errors[left_wrist], 3 * at_tracked[left_wrist]) << "half a guess is no tracked hand";
    } else if (weight == 0.0f) {
      EXPECT_EQ(errors[left_wrist], at_tracked[left_wrist]);
    }
    previous = errors[left_wrist];
  }
  fading.fading_guess = {FadingGuess{.weight = 0.2f, .seconds = 2.0f}, FadingGuess{.weight = 0.6f, .seconds = 1.0f}};
  EXPECT_EQ(FadingGuessFor(fading, left_wrist).weight, 0.2f);
  EXPECT_EQ(FadingGuessFor(fading, right_wrist).weight, 0.6f);
  EXPECT_EQ(FadingGuessFor(fading, 0).weight, 0.6f);  // the body: the heavier guess
}

TEST(ExpectedLandmarkErrorsTest, EveryReconstructedFrameCarriesThem) {
  const testing::SyntheticReconstructionSetup setup = testing::MakeSyntheticReconstructionSetup({}, 60);
  ReconstructionOptions options;
  options.ankle_candidates = 60;
  options.pose_neighbours = 40;
  auto frames = ReconstructOffline(setup.database, options, testing::WristSamplesOf(setup));
  ASSERT_TRUE(frames.ok()) << frames.status();
  ASSERT_FALSE(frames->empty());
  for (const ReconstructedFrame& frame : *frames) {
    for (int k = 0; k < kNumBodyLandmarks; ++k) {
      EXPECT_TRUE(std::isfinite(frame.landmark_error[k]));
      EXPECT_GT(frame.landmark_error[k], 0.0f) << "frame " << frame.index << " " << kBodyLandmarkNames[k];
    }
    EXPECT_TRUE(std::isfinite(frame.diagnostics.session_log_cost));
  }
}

}  // namespace
}  // namespace mocap

namespace mocap {
namespace {

TEST(AddGripUncertaintyTest, TheWristsTakeTheGripTimesTheirElbowsAngle) {
  const LandmarkErrors tracked = ExpectedLandmarkErrors({.distance = 0.5f, .wrist_fit = 0.01f, .solver_cost = 20.0f});
  LandmarkErrors errors = tracked;
  AddGripUncertainty(0.0f, &errors);
  EXPECT_EQ(errors, tracked);          // no grip: as they were
  AddGripUncertainty(0.36f, &errors);  // 9 cm past a 25 cm forearm
  for (int k = 0; k < kNumBodyLandmarks; ++k) {
    if (k == 6 || k == 7) {
      EXPECT_FLOAT_EQ(errors[k], std::hypot(tracked[k], 0.36f * tracked[k - 2])) << kBodyLandmarkNames[k];
      EXPECT_GT(errors[k], tracked[k]);
    } else {
      EXPECT_EQ(errors[k], tracked[k]) << kBodyLandmarkNames[k];
    }
  }
}

}  // namespace
}  // namespace mocap

// How sure the engine is of each body landmark it answers with (issue #25 item 1, docs/method.md
// "Confidence"): an expected error in metres per landmark and frame, told from what the engine
// already knows — how unlike the database the query is (the eq. 8 distance of its nearest database
// frame, A5), how well the solved body meets the wrists and how hard the A6 solve had to pull
// (its energy, now and over the session's last seconds: a body the database lacks keeps costing)
// — through a calibration fitted on development data (eval/fit_confidence.py).
#pragma once

#include <array>

#include "motion/reconstruct/wrist_resampler.h"
#include "motion/skeleton/body_topology.h"

namespace mocap {

using LandmarkErrors = std::array<float, kNumBodyLandmarks>;  // metres, BodyLandmarkJoints order

// What a frame's confidence is told from.
struct ConfidenceCues {
  float distance = 0;          // eq. 8 distance of the nearest database frame
  float wrist_fit = 0;         // metres: mean distance of the solved wrists from their targets (A6)
  float solver_cost = 0;       // A6 energy at the solution
  float session_log_cost = 0;  // SessionCost: the mean log energy over the session's last seconds
  // Per hand (left, right), seconds its input has not been real: across a dropout bridged by
  // interpolation the seconds to the nearer real sample, for a hand held by the other one
  // (one_hand_bridge.h) the seconds since it was lost; 0 when tracked.
  std::array<float, 2> untracked_seconds{};
  // Per hand, how much of a hand that came back is still the guess (OneHandBridge's cross-fade):
  // its landmarks' error falls from the guess's to the tracked one's with that weight.
  std::array<FadingGuess, 2> fading_guess{};
};

// The untracked seconds that bear on `landmark`: its own hand's for an arm's shoulder, elbow and
// wrist, the longer of the two for the rest of the body.
float UntrackedSecondsFor(const ConfidenceCues& cues, int landmark);
// The fading guess that bears on `landmark`, by the same rule: its own hand's for an arm, the
// heavier of the two for the rest.
FadingGuess FadingGuessFor(const ConfidenceCues& cues, int landmark);

// The causal mean of the log A6 energy over a session: the plain mean over its first
// `window_seconds`, then an exponential mean of that time constant. One per session (across its
// segments: the same person).
class SessionCost {
 public:
  explicit SessionCost(double frame_time, double window_seconds = 10.0);
  // Adds a frame's energy; returns the mean log energy including it.
  float Add(float solver_cost);
  // The mean so far, and how many frames it is over (0: none yet).
  float mean() const { return static_cast<float>(mean_log_); }
  long frames() const { return frames_; }

 private:
  double window_frames_;
  long frames_ = 0;
  double mean_log_ = 0;
};

// log(cost) as the calibration takes it (an energy of 0 stays finite).
float LogSolverCost(float solver_cost);

// The expected error of each landmark, metres.
LandmarkErrors ExpectedLandmarkErrors(const ConfidenceCues& cues);

// A device held `grip_over_forearm` forearm lengths past the wrist (grip_offset.h): each wrist is
// found back along the body's forearm, whose direction is off by about its elbow's error over the
// forearm's length, so the wrist's expected error takes grip × that angle in quadrature. Not fitted:
// geometry (phone_in_hand, docs/evaluation.md stop 64).
void AddGripUncertainty(float grip_over_forearm, LandmarkErrors* errors);

}  // namespace mocap

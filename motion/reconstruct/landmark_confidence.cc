#include "motion/reconstruct/landmark_confidence.h"

#include <algorithm>
#include <cmath>

namespace mocap {
namespace {

// The calibration of docs/method.md "Confidence", fitted on development data only
// (`eval/fit_confidence.py` reproduces every constant). A landmark whose input is real:
//   log e_k = a_k + b_d·log(d + 1e-4) + b_w·log(w + 1e-4) + b_c·log(c + 1e-3) + b_s·S
// (d: eq. 8 distance, w: wrist fit in metres, c: A6 energy, S: the session's mean log energy),
// fitted by least squares of the log error on the full method's landmark errors (lag 5, 0.5 cm
// noise) in two regimes weighted alike — the development split (the database has the performer's
// style) and the same takes with their style left out of the database — then each a_k raised by
// the mean of exp(residual) so that the mean error, not the median, is predicted.
constexpr std::array<float, kNumBodyLandmarks> kLogBase = {-3.4399f, -3.3447f, -3.3783f, -3.3913f, -3.4470f,
                                                           -3.4849f, -4.7989f, -4.8166f, -3.4359f, -3.4146f,
                                                           -3.3197f, -3.2293f, -3.1313f, -3.0885f};
constexpr float kDistanceExponent = 0.0724f;
constexpr float kWristFitExponent = 0.0804f;
constexpr float kCostExponent = 0.0389f;
constexpr float kSessionCostExponent = 0.3186f;
// A landmark whose input is not real (u = UntrackedSecondsFor > 0): the solve's cues say little
// there (the body meets a guess well), so a model of its own,
//   log e_k = a'_k + b_u·log(1 + u / 0.1 s),
// fitted the same way on the development split's takes streamed with dropouts of 0.1–5 s and with
// the left hand alone lost for 1–5 s (eval/device_input.h); a'_k shared by a left and right pair.
constexpr std::array<float, kNumBodyLandmarks> kUntrackedLogBase = {-3.3065f, -3.2541f, -3.2027f, -3.2027f, -2.7423f,
                                                                    -2.7423f, -2.4169f, -2.4169f, -3.2948f, -3.2948f,
                                                                    -3.0926f, -3.0926f, -2.8614f, -2.8614f};
constexpr float kUntrackedExponent = 0.3550f;
constexpr float kUntrackedScaleSeconds = 0.1f;

// The hand an arm's landmark follows (0 left, 1 right), -1 for the rest of the body:
// kBodyLandmarkNames 2..7 are the left and right shoulder, elbow and wrist, alternating.
int ArmSideOf(int landmark) { return landmark >= 2 && landmark <= 7 ? landmark % 2 : -1; }

float UntrackedError(int landmark, float seconds) {
  return std::exp(kUntrackedLogBase[landmark] + kUntrackedExponent * std::log1p(seconds / kUntrackedScaleSeconds));
}

}  // namespace

SessionCost::SessionCost(double frame_time, double window_seconds)
    : window_frames_(std::max(1.0, window_seconds / frame_time)) {}

float SessionCost::Add(float solver_cost) {
  ++frames_;
  const double weight = std::max(1.0 / static_cast<double>(frames_), 1.0 / window_frames_);
  mean_log_ += weight * (LogSolverCost(solver_cost) - mean_log_);
  return static_cast<float>(mean_log_);
}

float LogSolverCost(float solver_cost) { return std::log(std::max(0.0f, solver_cost) + 1e-3f); }

float UntrackedSecondsFor(const ConfidenceCues& cues, int landmark) {
  if (const int side = ArmSideOf(landmark); side >= 0) return cues.untracked_seconds[side];
  return std::max(cues.untracked_seconds[0], cues.untracked_seconds[1]);
}

FadingGuess FadingGuessFor(const ConfidenceCues& cues, int landmark) {
  if (const int side = ArmSideOf(landmark); side >= 0) return cues.fading_guess[side];
  const auto& [left, right] = cues.fading_guess;
  return left.weight >= right.weight ? left : right;
}

LandmarkErrors ExpectedLandmarkErrors(const ConfidenceCues& cues) {
  const float shared = kDistanceExponent * std::log(std::max(0.0f, cues.distance) + 1e-4f) +
                       kWristFitExponent * std::log(std::max(0.0f, cues.wrist_fit) + 1e-4f) +
                       kCostExponent * LogSolverCost(cues.solver_cost) + kSessionCostExponent * cues.session_log_cost;
  LandmarkErrors errors;
  for (int k = 0; k < kNumBodyLandmarks; ++k) {
    const float untracked = UntrackedSecondsFor(cues, k);
    if (untracked > 0) {
      errors[k] = UntrackedError(k, untracked);
      continue;
    }
    errors[k] = std::exp(kLogBase[k] + shared);
    // A position part guess, part input: its error is at most the blend of the two errors
    // (triangle inequality), which the guess's model and the tracked one predict.
    if (const FadingGuess fading = FadingGuessFor(cues, k); fading.weight > 0) {
      const float w = std::min(fading.weight, 1.0f);
      errors[k] = w * std::max(UntrackedError(k, std::max(fading.seconds, 0.0f)), errors[k]) + (1 - w) * errors[k];
    }
  }
  return errors;
}

void AddGripUncertainty(float grip_over_forearm, LandmarkErrors* errors) {
  if (!(grip_over_forearm > 0)) return;
  for (const auto& [elbow, wrist] : {std::pair{4, 6}, std::pair{5, 7}}) {  // kBodyLandmarkNames' order
    (*errors)[wrist] = std::hypot((*errors)[wrist], grip_over_forearm * (*errors)[elbow]);
  }
}

}  // namespace mocap

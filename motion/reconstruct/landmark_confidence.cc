#include "motion/reconstruct/landmark_confidence.h"

#include <algorithm>
#include <cmath>

namespace mocap {
namespace {

// The calibration of docs/method.md "Confidence": log e_k = a_k + b·log d + c·D, with d the frame's
// eq. 8 distance and D the session's mean log distance, fitted by least squares of log error on
// the full method's landmark errors (lag 5, 0.5 cm noise) in two development regimes weighted
// alike — the development split (the database has the performer's style) and the same takes with
// their style left out of the database — then each a_k raised by the mean of exp(residual) so the
// mean error, not the median, is predicted. `eval/fit_confidence.py` reproduces it.
constexpr std::array<float, kNumBodyLandmarks> kLogBase = {-2.1286f, -2.1063f, -2.1053f, -2.1200f, -2.1551f,
                                                           -2.1968f, -3.6827f, -3.6800f, -2.1289f, -2.1079f,
                                                           -2.0710f, -1.9312f, -1.9619f, -1.8303f};
constexpr float kDistanceExponent = 0.0586f;
constexpr float kSessionExponent = 0.2384f;
constexpr float kDistanceFloor = 1e-4f;

}  // namespace

SessionNovelty::SessionNovelty(double frame_time, double window_seconds)
    : window_frames_(std::max(1.0, window_seconds / frame_time)) {}

float SessionNovelty::Add(float distance) {
  ++frames_;
  const double weight = std::max(1.0 / static_cast<double>(frames_), 1.0 / window_frames_);
  mean_log_ += weight * (LogNoveltyDistance(distance) - mean_log_);
  return static_cast<float>(mean_log_);
}

float LogNoveltyDistance(float distance) { return std::log(std::max(0.0f, distance) + kDistanceFloor); }

LandmarkErrors ExpectedLandmarkErrors(float distance, float session_log_distance) {
  const float shared = kDistanceExponent * LogNoveltyDistance(distance) + kSessionExponent * session_log_distance;
  LandmarkErrors errors;
  for (int k = 0; k < kNumBodyLandmarks; ++k) errors[k] = std::exp(kLogBase[k] + shared);
  return errors;
}

}  // namespace mocap

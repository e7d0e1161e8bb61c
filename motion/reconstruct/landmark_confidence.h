// How sure the engine is of each body landmark it answers with (issue #25 item 1, docs/method.md
// "Confidence"): an expected error in metres per landmark and frame, told from how unlike the
// database the query is — the eq. 8 distance of its nearest database frame (A5), now and over the
// session's last seconds (a body the database lacks stays unlike it) — through a calibration fitted
// on development data (eval/fit_confidence.py).
#pragma once

#include <array>

#include "motion/skeleton/body_topology.h"

namespace mocap {

using LandmarkErrors = std::array<float, kNumBodyLandmarks>;  // metres, BodyLandmarkJoints order

// The causal mean of the log eq. 8 distance over a session: the plain mean over its first
// `window_seconds`, then an exponential mean of that time constant. One per session (across its
// segments: the same person).
class SessionNovelty {
 public:
  explicit SessionNovelty(double frame_time, double window_seconds = 10.0);
  // Adds a frame's distance; returns the mean log distance including it.
  float Add(float distance);

 private:
  double window_frames_;
  long frames_ = 0;
  double mean_log_ = 0;
};

// log(distance) as the calibration takes it (distances of 0 stay finite).
float LogNoveltyDistance(float distance);

// The expected error of each landmark, metres, from the frame's eq. 8 distance and the session's
// mean log distance (SessionNovelty).
LandmarkErrors ExpectedLandmarkErrors(float distance, float session_log_distance);

}  // namespace mocap

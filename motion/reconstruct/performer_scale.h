// The performer's size from the wrists alone (issue #22): the database knows how wrists move on
// its own body, so the factor that brings the input nearest to the database's wrist features
// (docs/method.md A3, eq. 2) is the input's size relative to the database body. Unlike a wrist height,
// it reads content and size together: a bow's low hands match the database's bent bodies at the
// performer's own size, not a standing body at a smaller one.
//
// The A1 wrist features are linear in a scaling of the world about any ground point (the
// reference frame's origin lies on the ground below the wrists), so the features of the input
// multiplied by k are k times the input's features: one feature per sampled frame, scored at
// every candidate k against the exact 1-nearest database frame.
#pragma once

#include <span>
#include <vector>

#include "absl/status/statusor.h"
#include "motion/reconstruct/reconstruction_database.h"
#include "motion/reconstruct/wrist_resampler.h"

namespace mocap {

struct PerformerScaleOptions {
  // Candidate input multipliers, a geometric grid over [min_scale, max_scale] (a body 0.7–1.4
  // times the database's: a child to a tall adult against a 1.6–1.7 m database actor).
  float min_scale = 0.7f, max_scale = 1.45f;
  int steps = 31;
  int frame_step = 3;           // score every n-th frame at the database rate
  float kept_fraction = 0.75f;  // trimmed mean: the best-matching fraction of sampled frames
  float min_seconds = 1.0f;     // less input than this: no estimate (scale 1)
};

struct PerformerScaleEstimate {
  float scale = 1.0f;  // multiply the input by it to bring the performer to the database body
  int frames = 0;      // frames scored
  // The fit (trimmed mean of eq. 2 to the nearest database frame) at each candidate, and at 1.
  std::vector<float> candidates, cost;
  float cost_at_one = 0.0f;
};

// Input samples in metres, Y up, ground at y = 0, strictly increasing times (as the session takes
// them). InvalidArgument for non-finite samples.
absl::StatusOr<PerformerScaleEstimate> EstimatePerformerScale(const ReconstructionDatabase& database,
                                                              std::span<const WristSample> samples,
                                                              const PerformerScaleOptions& options = {});

}  // namespace mocap

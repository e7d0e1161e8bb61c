// A6's E_prior weight for a session unlike the database (issue #22, docs/method.md "A session
// unlike the database"). When the person, the lab or the device is one the database lacks, the A6
// solve keeps paying a high energy: no pose near the neighbours' meets the targets, and meeting
// them bends the body away from any pose the database holds (the hands are put on the input after
// A7 by the arm IK anyway). There the prior is worth more: the prior weight rises with the
// session's mean log A6 energy (SessionCost, which the confidence reads too), from the configured
// weight at `from_log_cost` to `max_factor` times it at `to_log_cost`. In-lab sessions stay below
// `from_log_cost` and are solved as before. (Measured on development data: trusting the wrists
// less helps too, the ankles less hurts; docs/method.md.)
#pragma once

#include "motion/reconstruct/pose_solver.h"

namespace mocap {

struct UnfamiliarPriorOptions {
  float from_log_cost = 3.0f;  // session mean log A6 energy where the weight starts to rise
  float to_log_cost = 4.0f;    // … and where it reaches max_factor
  float max_factor = 4.0f;     // 1 = off
};

// The factor on the configured prior weight for a session whose mean log energy is
// `session_log_cost` over `session_frames` frames (none yet: 1).
float UnfamiliarPriorFactor(const UnfamiliarPriorOptions& options, float session_log_cost, long session_frames);

// The energy `solved` would have cost with the prior at its configured weight (`factor` was the
// session's): what the session's mean and the confidence read, so that raising the weight does
// not itself raise the cue that raised it.
float CostAtConfiguredPrior(const SolvedPose& solved, float configured_prior_weight, float factor);

}  // namespace mocap

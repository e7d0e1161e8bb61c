#include "motion/reconstruct/unfamiliar_prior.h"

#include <algorithm>

namespace mocap {

float UnfamiliarPriorFactor(const UnfamiliarPriorOptions& options, float session_log_cost, long session_frames) {
  if (session_frames <= 0 || options.max_factor <= 1.0f) return 1.0f;
  const float span = std::max(1e-3f, options.to_log_cost - options.from_log_cost);
  const float t = std::clamp((session_log_cost - options.from_log_cost) / span, 0.0f, 1.0f);
  return 1.0f + t * (options.max_factor - 1.0f);
}

float CostAtConfiguredPrior(const SolvedPose& solved, float configured_prior_weight, float factor) {
  return std::max(0.0f, solved.cost - (factor - 1.0f) * configured_prior_weight * solved.prior_cost);
}

}  // namespace mocap

// The A4 edge cost of docs/method.md (eqs. 3–7): w = β·s²·σ + (1−β)·d between a node at t−1 and a node
// at t (see ankle_path.h for the terms). Shared by the DP step, the start costs and the tests'
// reference implementation, so that all of them round the same way.
#pragma once

#include <cmath>

#include <Eigen/Core>

#include "motion/reconstruct/ankle_cloud.h"
#include "motion/reconstruct/ankle_path.h"

namespace mocap {

// The prior's factor β·s² (σ taken in units of 1/prior_length_scale).
inline float AnklePriorFactor(const AnklePathOptions& o) {
  return o.prior_weight * o.prior_length_scale * o.prior_length_scale;
}

// Height below which an ankle counts as touching the ground for SlideRule::kContact.
inline float AnkleContactCeiling(const AnklePathOptions& o) { return o.planted_ankle_height + o.contact_height; }

inline float AnkleEdgeCost(const AnkleCandidate& from, const AnkleCandidate& to, float dt, const AnklePathOptions& o) {
  float prior = 0.0f;
  float slide = 0.0f;
  const float ground = AnkleContactCeiling(o);
  for (int side = 0; side < 2; ++side) {
    const Eigen::Vector3f predicted = from.position[side] + dt * from.velocity[side];
    prior += (predicted - to.position[side]).squaredNorm();
    const Eigen::Vector3f step = to.position[side] - from.position[side];
    const float distance_sq = step.squaredNorm();
    if (distance_sq <= o.slide_distance * o.slide_distance) continue;
    const bool sliding = o.slide_rule == SlideRule::kPatent
                             ? std::abs(step.y()) < o.slide_height
                             : from.position[side].y() < ground && to.position[side].y() < ground;
    if (sliding) slide += std::exp(o.slide_weight * distance_sq);
  }
  return AnklePriorFactor(o) * prior + (1.0f - o.prior_weight) * slide;
}

}  // namespace mocap

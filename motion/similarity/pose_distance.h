// Distance between two body point clouds after the optimal ground-plane alignment
// (docs/method.md B5–B6; Kovar, Gleicher & Pighin 2002): one rotation about the vertical and one
// ground translation for the whole pose, then a weighted sum of per-group point distances.
#pragma once

#include <array>

#include <Eigen/Core>

#include "motion/skeleton/body_topology.h"

namespace mocap {

// Group weights (docs/method.md B6), indexed by BodyGroup.
struct GroupWeights {
  std::array<float, kNumBodyGroups> weight{1, 1, 1, 1, 1, 1};
  static GroupWeights Uniform() { return {}; }
  static GroupWeights Locomotion() { return {{{1.0f, 0.5f, 0.75f, 0.75f, 2.0f, 2.0f}}}; }
  static GroupWeights UpperBody() { return {{{1.0f, 1.5f, 2.0f, 2.0f, 0.5f, 0.5f}}}; }
};

// Rotation about +Y (radians) and ground translation that best map `candidate` onto `query`.
struct GroundAlignment {
  float yaw = 0.0f;
  float x = 0.0f;
  float z = 0.0f;
};

struct PoseDistance {
  float total = 0.0f;
  std::array<float, kNumBodyGroups> per_group{};
  GroundAlignment alignment;
};

// Both clouds have kNumBodyGroups * points_per_group points (BodyPointsOfFrame), possibly for
// several frames in a row (a window: then `num_points` covers all of them). Point weights in the
// alignment are the group weights.
PoseDistance ComparePoses(const float* query, const float* candidate, int num_points, int points_per_group,
                          const GroupWeights& weights);

}  // namespace mocap

// The straightforward A4 DP step (docs/method.md A4, Algorithm 1) that AnkleDagStep must agree with:
// every node of `current` scans the predecessors by increasing path cost, one AnkleEdgeCost at a
// time, until a predecessor's path cost alone reaches the best total found. Kept for the tests
// and the benchmark (side by side with the fast step).
#pragma once

#include <vector>

#include "motion/reconstruct/ankle_path.h"

namespace mocap::testing {

void ReferenceAnkleDagStep(const std::vector<AnkleCandidate>& previous, const std::vector<float>& previous_cost,
                           const std::vector<AnkleCandidate>& current, float dt, const AnklePathOptions& options,
                           std::vector<float>* cost, std::vector<int>* from);

}  // namespace mocap::testing

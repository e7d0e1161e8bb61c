#include "tests/support/reference_ankle_dag_step.h"

#include <algorithm>
#include <limits>
#include <numeric>

#include "motion/reconstruct/ankle_edge_cost.h"

namespace mocap::testing {

void ReferenceAnkleDagStep(const std::vector<AnkleCandidate>& previous, const std::vector<float>& previous_cost,
                           const std::vector<AnkleCandidate>& current, float dt, const AnklePathOptions& options,
                           std::vector<float>* cost, std::vector<int>* from) {
  cost->assign(current.size(), std::numeric_limits<float>::infinity());
  from->assign(current.size(), 0);
  // Edge costs are never negative, so scanning predecessors by increasing path cost can stop at
  // the first one already costing more than the best found.
  std::vector<int> order(previous.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return previous_cost[a] < previous_cost[b]; });
  for (size_t k = 0; k < current.size(); ++k) {
    float best = std::numeric_limits<float>::infinity();
    int best_j = order[0];
    for (int j : order) {
      if (previous_cost[j] >= best) break;
      const float c = previous_cost[j] + AnkleEdgeCost(previous[j], current[k], dt, options);
      if (c < best) {
        best = c;
        best_j = j;
      }
    }
    (*cost)[k] = best;
    (*from)[k] = best_j;
  }
}

}  // namespace mocap::testing

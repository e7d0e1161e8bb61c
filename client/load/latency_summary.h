// Percentiles of a set of latencies, for the load generator's report.
#pragma once

#include <vector>

namespace mocap::load {

struct LatencySummary {
  long count = 0;
  double mean_ms = 0, p50_ms = 0, p90_ms = 0, p99_ms = 0, max_ms = 0;
};

// Nearest-rank percentiles (p99 of 100 values is the 99th smallest). Empty input: all zero.
LatencySummary Summarise(std::vector<double> milliseconds);

}  // namespace mocap::load

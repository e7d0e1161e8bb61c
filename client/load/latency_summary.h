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

// The same for each whole second of a run: element s summarises the latencies whose samples were
// sent in [s, s + 1) seconds after its start (`seconds_after_start`, one per latency; negative
// values go to second 0). Seconds with no latency are all zero; the result ends at the last
// second that has one.
std::vector<LatencySummary> SummariseBySecond(const std::vector<double>& milliseconds,
                                              const std::vector<double>& seconds_after_start);

}  // namespace mocap::load

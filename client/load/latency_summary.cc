#include "client/load/latency_summary.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace mocap::load {
namespace {

double NearestRank(const std::vector<double>& sorted, double percentile) {
  const auto rank = static_cast<size_t>(std::ceil(percentile / 100.0 * static_cast<double>(sorted.size())));
  return sorted[std::clamp<size_t>(rank, 1, sorted.size()) - 1];
}

}  // namespace

LatencySummary Summarise(std::vector<double> milliseconds) {
  LatencySummary summary;
  if (milliseconds.empty()) return summary;
  std::sort(milliseconds.begin(), milliseconds.end());
  summary.count = static_cast<long>(milliseconds.size());
  summary.mean_ms = std::accumulate(milliseconds.begin(), milliseconds.end(), 0.0) / static_cast<double>(summary.count);
  summary.p50_ms = NearestRank(milliseconds, 50);
  summary.p90_ms = NearestRank(milliseconds, 90);
  summary.p99_ms = NearestRank(milliseconds, 99);
  summary.max_ms = milliseconds.back();
  return summary;
}

}  // namespace mocap::load

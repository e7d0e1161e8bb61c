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

std::vector<LatencySummary> SummariseBySecond(const std::vector<double>& milliseconds,
                                              const std::vector<double>& seconds_after_start) {
  std::vector<std::vector<double>> by_second;
  const size_t n = std::min(milliseconds.size(), seconds_after_start.size());
  for (size_t i = 0; i < n; ++i) {
    const auto second = static_cast<size_t>(std::max(0.0, std::floor(seconds_after_start[i])));
    if (second >= by_second.size()) by_second.resize(second + 1);
    by_second[second].push_back(milliseconds[i]);
  }
  std::vector<LatencySummary> summaries;
  summaries.reserve(by_second.size());
  for (std::vector<double>& second : by_second) summaries.push_back(Summarise(std::move(second)));
  return summaries;
}

}  // namespace mocap::load

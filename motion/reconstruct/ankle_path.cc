#include "motion/reconstruct/ankle_path.h"

#include <algorithm>
#include <optional>

#include "motion/core/gaussian_kernel.h"
#include "motion/core/str_cat.h"
#include "motion/reconstruct/ankle_edge_cost.h"
#include "motion/reconstruct/wrist_smoother.h"

namespace mocap {
AnklePair SmoothAnkleAt(const std::vector<AnklePair>& ankles, const std::vector<float>& kernel, int t, int available,
                        float edge_fit_step) {
  const int radius = static_cast<int>(kernel.size()) / 2;
  AnklePair sum = {Eigen::Vector3f::Zero(), Eigen::Vector3f::Zero()};
  for (int i = -radius; i <= radius; ++i) {
    const int s = std::clamp(t + i, 0, available - 1);
    for (int side = 0; side < 2; ++side) sum[side] += kernel[i + radius] * ankles[s][side];
  }
  const bool past_start = t - radius < 0, past_end = t + radius >= available;
  if (edge_fit_step < 0.0f || available < 2 || past_start == past_end) return sum;  // inside, or both ends
  const int low = std::max(0, t - radius), high = std::min(available - 1, t + radius);
  std::optional<SmoothedWrists> line;  // A2's weighted line fit, over the same frames and weights
  for (int side = 0; side < 2; ++side) {
    // The end's last step: a foot still there keeps the end frame (a line would extrapolate the
    // path's wobble), a moving one is followed.
    const Eigen::Vector3f step =
        past_end ? ankles[available - 1][side] - ankles[available - 2][side] : ankles[1][side] - ankles[0][side];
    if (step.norm() <= edge_fit_step) continue;
    if (!line) line = LocalLinearWrists(ankles, t, available - 1, kernel, 1.0f);
    float lowest = ankles[low][side].y(), highest = lowest;
    for (int f = low + 1; f <= high; ++f) {
      lowest = std::min(lowest, ankles[f][side].y());
      highest = std::max(highest, ankles[f][side].y());
    }
    sum[side] = line->position[side];
    sum[side].y() = std::clamp(sum[side].y(), lowest, highest);  // a line through a lifting foot must not dig it in
  }
  return sum;
}

void AddAnkleDataCost(const std::vector<AnkleCandidate>& cloud, const AnklePathOptions& options,
                      std::vector<float>* cost) {
  if (options.data_weight <= 0.0f) return;
  const float weight = options.data_weight * options.prior_length_scale * options.prior_length_scale;
  for (size_t k = 0; k < cloud.size(); ++k) (*cost)[k] += weight * cloud[k].wrist_distance;
}

std::vector<float> AnkleStartCosts(const std::optional<AnkleCandidate>& start, const std::vector<AnkleCandidate>& first,
                                   float dt, const AnklePathOptions& options) {
  std::vector<float> cost(first.size(), 0.0f);
  if (start) {
    for (size_t k = 0; k < first.size(); ++k) cost[k] = AnkleEdgeCost(*start, first[k], dt, options);
  }
  AddAnkleDataCost(first, options, &cost);
  return cost;
}

void AnkleWindowDp::Start(const std::optional<AnkleCandidate>& start, const std::vector<AnkleCandidate>& cloud) {
  cost_ = AnkleStartCosts(start, cloud, frame_time_, options_);
  from_.assign(1, std::vector<int>(cloud.size(), -1));
}

void AnkleWindowDp::Step(const std::vector<AnkleCandidate>& previous, const std::vector<AnkleCandidate>& cloud) {
  std::vector<int>& from = from_.emplace_back();
  AnkleDagStep(previous, cost_, cloud, frame_time_, options_, &next_cost_, &from);
  AddAnkleDataCost(cloud, options_, &next_cost_);
  cost_.swap(next_cost_);
}

AnkleWindowResult AnkleWindowDp::Best(const std::vector<std::vector<AnkleCandidate>>& clouds) const {
  const int frames = this->frames();
  AnkleWindowResult result;
  result.nodes.resize(frames);
  const auto last = std::min_element(cost_.begin(), cost_.end());
  result.cost = *last;
  result.nodes[frames - 1] = static_cast<int>(last - cost_.begin());
  for (int t = frames - 1; t > 0; --t) result.nodes[t - 1] = from_[t][result.nodes[t]];
  for (int t = 0; t < frames; ++t) result.ankles.push_back(AnklesOf(clouds[t][result.nodes[t]]));
  return result;
}

absl::StatusOr<AnkleWindowResult> SolveAnkleWindow(const std::vector<std::vector<AnkleCandidate>>& clouds,
                                                   const std::optional<AnkleCandidate>& start, double frame_time,
                                                   const AnklePathOptions& options, const std::atomic<bool>* cancel) {
  if (clouds.empty()) return absl::InvalidArgumentError("ankle window has no frames");
  for (size_t t = 0; t < clouds.size(); ++t) {
    if (clouds[t].empty()) return absl::InvalidArgumentError(StrCat("ankle cloud of frame ", t, " is empty"));
  }
  AnkleWindowDp dp(frame_time, options);
  dp.Start(start, clouds[0]);
  for (size_t t = 1; t < clouds.size(); ++t) {
    if (cancel != nullptr && cancel->load(std::memory_order_relaxed))
      return absl::CancelledError("ankle path cancelled");
    dp.Step(clouds[t - 1], clouds[t]);
  }
  return dp.Best(clouds);
}

std::vector<AnklePair> SmoothAnkles(const std::vector<AnklePair>& ankles, float sigma_frames, float edge_fit_step) {
  if (sigma_frames <= 0.0f || ankles.size() < 2) return ankles;
  const std::vector<float> kernel = GaussianKernel(sigma_frames);
  const int n = static_cast<int>(ankles.size());
  std::vector<AnklePair> out(n);
  for (int t = 0; t < n; ++t) out[t] = SmoothAnkleAt(ankles, kernel, t, n, edge_fit_step);
  return out;
}

absl::StatusOr<std::vector<AnklePair>> SolveAnklePath(const std::vector<std::vector<AnkleCandidate>>& clouds,
                                                      int window, double frame_time, const AnklePathOptions& options) {
  if (clouds.empty()) return std::vector<AnklePair>();
  const int frames = static_cast<int>(clouds.size());
  const int step = window > 0 ? window : frames;
  std::vector<AnklePair> path;
  std::optional<AnkleCandidate> start;
  for (int begin = 0; begin < frames; begin += step) {
    const int end = std::min(frames, begin + step);
    const std::vector<std::vector<AnkleCandidate>> part(clouds.begin() + begin, clouds.begin() + end);
    absl::StatusOr<AnkleWindowResult> solved = SolveAnkleWindow(part, start, frame_time, options);
    if (!solved.ok()) return solved.status();
    path.insert(path.end(), solved->ankles.begin(), solved->ankles.end());
    start = part.back()[solved->nodes.back()];
  }
  return SmoothAnkles(path, options.smoothing_sigma_frames, options.edge_fit_speed * static_cast<float>(frame_time));
}

}  // namespace mocap

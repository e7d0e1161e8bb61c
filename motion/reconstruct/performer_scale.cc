#include "motion/reconstruct/performer_scale.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "motion/core/gaussian_kernel.h"
#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"
#include "motion/reconstruct/ankle_cloud.h"
#include "motion/reconstruct/wrist_smoother.h"

namespace mocap {
namespace {

// The input on the database's frame grid, as the session sees it (segments joined: a gap only
// costs the frames it lacks).
absl::StatusOr<std::vector<std::array<Eigen::Vector3f, 2>>> OnDatabaseGrid(double frame_time,
                                                                           std::span<const WristSample> samples) {
  WristResampler resampler(frame_time, /*max_gap_seconds=*/2.0);
  std::vector<GridSample> grid;
  for (const WristSample& s : samples) {
    if (!s.left.allFinite() || !s.right.allFinite() || !std::isfinite(s.time))
      return absl::InvalidArgumentError("a wrist sample is not finite");
    MOCAP_RETURN_IF_ERROR(resampler.Push(s, &grid));
  }
  resampler.Flush(&grid);
  std::vector<std::array<Eigen::Vector3f, 2>> out;
  out.reserve(grid.size());
  for (const GridSample& g : grid) out.push_back({g.left, g.right});
  return out;
}

float TrimmedMean(std::vector<float>& values, float kept_fraction) {
  const size_t kept = std::max<size_t>(1, static_cast<size_t>(kept_fraction * values.size()));
  std::nth_element(values.begin(), values.begin() + (kept - 1), values.end());
  double sum = 0;
  for (size_t i = 0; i < kept; ++i) sum += values[i];
  return static_cast<float>(sum / kept);
}

}  // namespace

absl::StatusOr<PerformerScaleEstimate> EstimatePerformerScale(const ReconstructionDatabase& database,
                                                              std::span<const WristSample> samples,
                                                              const PerformerScaleOptions& options) {
  if (!(options.min_scale > 0 && options.max_scale >= options.min_scale) || options.steps < 1 ||
      options.frame_step < 1 || !(options.kept_fraction > 0 && options.kept_fraction <= 1)) {
    return absl::InvalidArgumentError("performer scale options out of range");
  }
  MOCAP_ASSIGN_OR_RETURN(auto grid, OnDatabaseGrid(database.frame_time(), samples));
  PerformerScaleEstimate estimate;
  const int frames = static_cast<int>(grid.size());
  if (frames * database.frame_time() < options.min_seconds) return estimate;

  // One A1 wrist feature per sampled frame (the session's A2 fit: local linear, σ = 1 frame).
  const std::vector<float> kernel = GaussianKernel(1.0f);
  const float rate = static_cast<float>(1.0 / database.frame_time());
  const WristFeatureOptions& feature_options = database.wrist_feature_options();
  std::vector<std::array<float, kWristFeatureDims>> features;
  float heading = 0.0f;
  for (int t = 0; t < frames; t += options.frame_step) {
    const SmoothedWrists wrists = LocalLinearWrists(grid, t, frames - 1, kernel, rate);
    const ReferenceFrame ref = WristReferenceFrame(wrists.position[0], wrists.position[1], heading, &heading);
    std::array<float, kWristFeatureDims> f;
    WristFeature(WristQueryFeatures(ref, wrists), feature_options, f.data());
    features.push_back(f);
  }
  estimate.frames = static_cast<int>(features.size());

  const float log_min = std::log(options.min_scale), log_max = std::log(options.max_scale);
  std::vector<float> distances(features.size());
  auto cost_at = [&](float k) -> absl::StatusOr<float> {
    for (size_t i = 0; i < features.size(); ++i) {
      std::array<float, kWristFeatureDims> scaled;
      for (int d = 0; d < kWristFeatureDims; ++d) scaled[d] = k * features[i][d];
      MOCAP_ASSIGN_OR_RETURN(std::vector<Neighbour> nearest, database.wrist_index().Search(scaled.data(), 1));
      distances[i] = nearest.front().distance;
    }
    return TrimmedMean(distances, options.kept_fraction);
  };

  float best = 0;
  for (int i = 0; i < options.steps; ++i) {
    const float k =
        options.steps == 1 ? options.min_scale : std::exp(log_min + (log_max - log_min) * i / (options.steps - 1));
    MOCAP_ASSIGN_OR_RETURN(const float cost, cost_at(k));
    estimate.candidates.push_back(k);
    estimate.cost.push_back(cost);
    if (i == 0 || cost < best) {
      best = cost;
      estimate.scale = k;
    }
  }
  MOCAP_ASSIGN_OR_RETURN(estimate.cost_at_one, cost_at(1.0f));
  return estimate;
}

}  // namespace mocap

#include "motion/reconstruct/wrist_reach.h"

#include <algorithm>
#include <cmath>

namespace mocap {
namespace {

int Bin(float metres, float bin_metres, int bins) {
  return std::clamp(static_cast<int>(metres / bin_metres), 0, bins - 1);
}

// The value below which `quantile` of the counted samples lie, rounded down to its bin's lower
// edge (a bound that errs towards the database's size: rounding never sizes a body up).
template <size_t N>
float Quantile(const std::array<int, N>& bins, long count, float quantile, float bin_metres) {
  const long rank = std::min(count - 1, static_cast<long>(quantile * static_cast<float>(count)));
  long below = 0;
  for (size_t b = 0; b < N; ++b) {
    below += bins[b];
    if (below > rank) return static_cast<float>(b) * bin_metres;
  }
  return static_cast<float>(N - 1) * bin_metres;
}

}  // namespace

WristReach MeasureWristReach(std::span<const FrameFeatures> frames) {
  WristReach reach;
  for (const FrameFeatures& f : frames) {
    const float* l = f.wrist_position[0];
    const float* r = f.wrist_position[1];
    reach.separation = std::max(reach.separation, std::hypot(l[0] - r[0], l[1] - r[1], l[2] - r[2]));
    reach.height = std::max({reach.height, l[1], r[1]});
  }
  return reach;
}

absl::Status ReachHistogram::Add(const WristSample& s) {
  for (int hand = 0; hand < 2; ++hand) {
    if (s.tracked[hand] && !(hand == 0 ? s.left : s.right).allFinite())
      return absl::InvalidArgumentError("a tracked wrist sample is not finite");
  }
  for (int hand = 0; hand < 2; ++hand) {
    if (!s.tracked[hand]) continue;
    ++height_[Bin((hand == 0 ? s.left : s.right).y(), kBinMetres, kBins)];
    ++height_count_;
  }
  std::array<bool, 2> still{false, false};
  for (int hand = 0; hand < 2; ++hand) {
    if (s.tracked[hand]) {
      still[hand] = still_[hand].Update(hand == 0 ? s.left : s.right, s.time) >= kStillSeconds;
    } else {
      still_[hand].Forget();
    }
  }
  if (s.tracked[0] && s.tracked[1] && !still[0] && !still[1]) {
    ++separation_[Bin((s.left - s.right).norm(), kBinMetres, kBins)];
    ++separation_count_;
  }
  if (samples_++ == 0) first_time_ = s.time;
  last_time_ = s.time;
  return absl::OkStatus();
}

absl::StatusOr<ReachScale> ReachHistogram::Scale(const WristReach& database, const ReachScaleOptions& options) const {
  if (!(database.separation > 0.0f) || !(database.height > 0.0f)) {
    return absl::InvalidArgumentError("the database has no wrist reach (no frames)");
  }
  ReachScale scale;
  if (samples_ < 2 || last_time_ - first_time_ < options.min_seconds) return scale;
  float bound = 1.0f;
  if (separation_count_ > 0) {
    scale.separation = Quantile(separation_, separation_count_, options.quantile, kBinMetres);
    if (scale.separation > 0.0f) bound = std::min(bound, database.separation / scale.separation);
  }
  if (height_count_ > 0) {
    scale.height = Quantile(height_, height_count_, options.quantile, kBinMetres);
    if (scale.height > 0.0f) bound = std::min(bound, database.height / scale.height);
  }
  scale.input_scale = std::max(options.min_scale, bound);
  return scale;
}

absl::StatusOr<ReachScale> InputScaleFromReach(const WristReach& database, std::span<const WristSample> samples,
                                               const ReachScaleOptions& options) {
  ReachHistogram histogram;
  for (const WristSample& s : samples) {
    if (absl::Status added = histogram.Add(s); !added.ok()) return added;
  }
  return histogram.Scale(database, options);
}

}  // namespace mocap

#include "motion/reconstruct/wrist_resampler.h"

#include <algorithm>
#include <cmath>

#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"

namespace mocap {
namespace {

Eigen::Vector3f& Hand(GridSample& sample, int side) { return side == 0 ? sample.left : sample.right; }

bool IsRealInput(int side, const std::array<float, 2>& untracked_seconds,
                 const std::array<FadingGuess, 2>& fading_guess) {
  return untracked_seconds[side] == 0 && fading_guess[side].weight == 0;
}

}  // namespace

WristResampler::WristResampler(double frame_time, double max_gap_seconds)
    : frame_time_(frame_time), max_gap_(max_gap_seconds) {}

absl::Status WristResampler::Check(const WristSample& sample) const {
  if (!std::isfinite(sample.time)) return absl::InvalidArgumentError("wrist sample time is not finite");
  if ((sample.tracked[0] && !sample.left.allFinite()) || (sample.tracked[1] && !sample.right.allFinite())) {
    return absl::InvalidArgumentError(StrCat("wrist sample at t = ", sample.time, " s is not finite (NaN or inf)"));
  }
  if (has_previous_ && sample.time <= previous_.time) {
    return absl::InvalidArgumentError(
        StrCat("wrist sample times must increase: ", sample.time, " s after ", previous_.time, " s"));
  }
  return absl::OkStatus();
}

absl::Status WristResampler::Push(const WristSample& sample, std::vector<GridSample>* out,
                                  std::array<float, 2> untracked_seconds, std::array<FadingGuess, 2> fading_guess,
                                  std::array<bool, 2> put_down) {
  MOCAP_RETURN_IF_ERROR(Check(sample));
  if (!sample.left.allFinite() || !sample.right.allFinite()) {  // a lost hand must be filled in first
    return absl::InvalidArgumentError(StrCat("wrist sample at t = ", sample.time, " s is not finite (NaN or inf)"));
  }
  const bool new_segment = !has_previous_ || sample.time - previous_.time > max_gap_;
  const Eigen::Vector3f positions[2] = {sample.left, sample.right};
  if (new_segment) {
    Release(/*flush=*/true, out);  // the previous segment's frames that waited for a repeating hand
    for (int side = 0; side < 2; ++side) {
      anchors_[side] = {
          .time = sample.time, .position = positions[side], .real = IsRealInput(side, untracked_seconds, fading_guess)};
    }
    grid_origin_ = sample.time;
    next_index_ = 0;
    typical_period_ = 0.0;
    GridSample first{.starts_segment = true,
                     .bridged = false,
                     .untracked_seconds = untracked_seconds,
                     .fading_guess = fading_guess,
                     .put_down = put_down,
                     .time = sample.time,
                     .left = sample.left,
                     .right = sample.right};
    out->push_back(first);
    next_index_ = 1;
  } else {
    const double span = sample.time - previous_.time;
    const bool bridged = typical_period_ > 0.0 && span > 2.0 * typical_period_;
    typical_period_ = typical_period_ > 0.0 && !bridged ? 0.9 * typical_period_ + 0.1 * span
                                                        : (typical_period_ > 0.0 ? typical_period_ : span);
    // Grid times in (previous, sample], with a tolerance of 1% of a frame: a tracker at the
    // database's nominal rate (e.g. a BVH's "Frame Time: 0.033333" against 1/30 s) drifts by
    // ~1e-4 s over ten seconds, and its last sample must still complete the last frame.
    for (;;) {
      const double t = grid_origin_ + static_cast<double>(next_index_) * frame_time_;
      if (t > sample.time + Slack()) break;
      const float a = static_cast<float>(std::clamp((t - previous_.time) / span, 0.0, 1.0));
      // The grid time that meets the new sample is input again, not a guess across the dropout.
      const bool guessed = bridged && t < sample.time - Slack();
      const float bridge = guessed ? static_cast<float>(std::min(t - previous_.time, sample.time - t)) : 0.0f;
      std::array<float, 2> untracked;
      std::array<FadingGuess, 2> fading;
      for (int side = 0; side < 2; ++side) {
        untracked[side] = std::max(bridge, (1 - a) * previous_untracked_[side] + a * untracked_seconds[side]);
        fading[side] = {.weight = (1 - a) * previous_fading_[side].weight + a * fading_guess[side].weight,
                        .seconds = (1 - a) * previous_fading_[side].seconds + a * fading_guess[side].seconds};
      }
      // Each hand held at its last new position until Advance places it towards the next one.
      waiting_.push_back(GridSample{.starts_segment = false,
                                    .bridged = guessed,
                                    .untracked_seconds = untracked,
                                    .fading_guess = fading,
                                    .put_down = a < 0.5f ? previous_put_down_ : put_down,
                                    .time = t,
                                    .left = anchors_[0].position,
                                    .right = anchors_[1].position});
      ++next_index_;
    }
    for (int side = 0; side < 2; ++side) {
      const bool real = IsRealInput(side, untracked_seconds, fading_guess);
      if (IsRepeat(side, positions[side], sample.time, real)) {
        ++repeated_hand_samples_;
      } else {
        Advance(side, {.time = sample.time, .position = positions[side], .real = real});
      }
    }
    Release(/*flush=*/false, out);
  }
  previous_ = sample;
  previous_untracked_ = untracked_seconds;
  previous_fading_ = fading_guess;
  previous_put_down_ = put_down;
  has_previous_ = true;
  return absl::OkStatus();
}

void WristResampler::Flush(std::vector<GridSample>* out) { Release(/*flush=*/true, out); }

bool WristResampler::IsRepeat(int side, const Eigen::Vector3f& position, double time, bool real) const {
  const Anchor& anchor = anchors_[side];
  return real && anchor.real && position == anchor.position && time - anchor.time <= kRepeatHoldSeconds;
}

void WristResampler::Advance(int side, const Anchor& next) {
  const Anchor& from = anchors_[side];
  const double span = next.time - from.time;
  for (GridSample& g : waiting_) {
    if (g.time <= from.time + Slack()) continue;  // placed by the anchor already
    const float a = static_cast<float>(std::clamp((g.time - from.time) / span, 0.0, 1.0));
    Hand(g, side) = (1 - a) * from.position + a * next.position;
  }
  anchors_[side] = next;
}

void WristResampler::Release(bool flush, std::vector<GridSample>* out) {
  const double reached = std::min(anchors_[0].time, anchors_[1].time) + Slack();
  while (!waiting_.empty() && (flush || waiting_.front().time <= reached)) {
    out->push_back(waiting_.front());
    waiting_.pop_front();
  }
}

}  // namespace mocap

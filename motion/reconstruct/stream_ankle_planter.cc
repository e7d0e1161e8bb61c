#include "motion/reconstruct/stream_ankle_planter.h"

#include <algorithm>
#include <cmath>

#include "motion/reconstruct/plausibility.h"

namespace mocap {

StreamAnklePlanter::StreamAnklePlanter(float planted_ankle_height, double frame_time, const FootskateOptions& options,
                                       float standing_hands_speed)
    : planted_height_(planted_ankle_height),
      rate_(static_cast<float>(1.0 / frame_time)),
      options_(options),
      standing_speed_(standing_hands_speed),
      hold_frames_(std::max(1, static_cast<int>(std::lround(options.stream_hold_seconds * rate_)))),
      short_frames_(HandsWindowFrames(frame_time, 0)),
      standing_frames_(HandsWindowFrames(frame_time, 1)),
      estimates_(static_cast<size_t>(hold_frames_)),
      hands_(static_cast<size_t>(standing_frames_ + 1)) {}

template <typename At>
bool StreamAnklePlanter::StandsOver(At at) const {
  // Over both windows of the guard (kHandsWindowsSeconds): the longer says the body stands, the
  // shorter that it has not just set off (a 2 s mean of a walk's first half second is still slow).
  for (const int frames : {short_frames_, standing_frames_}) {
    const size_t oldest = std::min(static_cast<size_t>(frames), hands_.size() - 1);
    const float seconds = static_cast<float>(oldest) / rate_;
    if (!((at(0) - at(oldest)).norm() < standing_speed_ * seconds)) return false;
  }
  return true;
}

bool StreamAnklePlanter::Stands() const {
  if (!(standing_speed_ > 0) || hands_.size() < 2) return false;
  if (StandsOver([&](size_t back) -> Eigen::Vector2f { return 0.5f * (hands_.Back(back)[0] + hands_.Back(back)[1]); }))
    return true;
  if (!options_.stream_stands_on_either_hand) return false;
  for (int side = 0; side < 2; ++side) {
    if (StandsOver([&](size_t back) -> const Eigen::Vector2f& { return hands_.Back(back)[side]; })) return true;
  }
  return false;
}

void StreamAnklePlanter::Next(AnklePair* ankles, const std::array<Eigen::Vector2f, 2>& hands) {
  hands_.Push(hands);
  const AnklePair estimate = *ankles;
  const float lifted_above = planted_height_ + options_.contact_height;
  for (int side = 0; side < 2; ++side) {
    Foot& foot = feet_[side];
    const Eigen::Vector3f& now = estimate[side];
    bool contact = false;
    if (!estimates_.empty()) {
      if (foot.planted) {
        // Held over the hold span, as the cleanup holds it; or the body stands and the foot has not lifted.
        const size_t span = std::min(static_cast<size_t>(hold_frames_), estimates_.size());
        contact = EstimateSaysPlanted(estimates_.Back(span - 1)[side], now, planted_height_,
                                      rate_ / static_cast<float>(span), options_) ||
                  (now.y() < lifted_above && Stands());
      } else {
        contact = EstimateSaysPlanted(estimates_.Back(0)[side], now, planted_height_, rate_, options_);
      }
    }
    if (contact) {
      if (!foot.planted) {
        foot.sum.setZero();
        foot.frames = 0;
      }
      foot.planted = true;
      foot.release_left = 0;
      foot.sum += now;
      ++foot.frames;
      (*ankles)[side] = foot.sum / static_cast<float>(foot.frames);
      continue;
    }
    if (foot.planted) {  // the contact ended: return from its mean, as the cleanup releases
      foot.planted = false;
      foot.release_offset = foot.sum / static_cast<float>(foot.frames) - now;
      foot.release_left = options_.release_frames;
    }
    if (foot.release_left > 0) {
      const float fraction = static_cast<float>(foot.release_left) / static_cast<float>(options_.release_frames + 1);
      (*ankles)[side] = now + fraction * foot.release_offset;
      --foot.release_left;
    }
  }
  estimates_.Push(estimate);
}

}  // namespace mocap

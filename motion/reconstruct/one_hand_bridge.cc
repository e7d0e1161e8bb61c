#include "motion/reconstruct/one_hand_bridge.h"

#include <algorithm>

namespace mocap {
namespace {

// Smoothstep weights, flat at both ends (u in [0, 1]).
float Smoothstep(double u) { return static_cast<float>(u * u * (3.0 - 2.0 * u)); }

}  // namespace

Eigen::Vector3f OneHandBridge::TravelVelocity(int side) const {
  const auto& recent = recent_[side];
  if (recent.size() < 2 || recent.back().first <= recent.front().first) return Eigen::Vector3f::Zero();
  Eigen::Vector3f velocity =
      (recent.back().second - recent.front().second) / static_cast<float>(recent.back().first - recent.front().first);
  velocity.y() = 0.0f;  // a body travels over the ground; a hand that rises or falls gestures
  return velocity;
}

void OneHandBridge::Carry(int side, const Eigen::Vector3f& offset) { catch_up_[side] = CatchUp{.offset = offset}; }

Eigen::Vector3f OneHandBridge::CatchUpStep(int side, double t) {
  std::optional<CatchUp>& c = catch_up_[side];
  if (!c) return Eigen::Vector3f::Zero();
  if (!c->start) c->start = t;
  const double u = std::min(1.0, (t - *c->start) / kCatchUpSeconds);
  const float w = Smoothstep(u);
  const Eigen::Vector3f step = (w - c->applied) * c->offset;
  c->applied = w;
  if (u >= 1.0) c.reset();
  return step;
}

bool OneHandBridge::Fill(WristSample* sample, std::array<float, 2>* untracked_seconds,
                         std::array<FadingGuess, 2>* fading_guess) {
  const std::array<bool, 2> tracked = sample->tracked;
  if (!tracked[0] && !tracked[1]) return false;
  for (int side = 0; side < 2; ++side) {
    if (!tracked[side] && !last_tracked_time_[side]) return false;
  }
  const double t = sample->time;
  const std::array<Eigen::Vector3f, 2> input = {sample->left, sample->right};
  std::array<Eigen::Vector3f, 2> position = input;
  std::array<FadingGuess, 2> fading{};
  for (int side = 0; side < 2; ++side) {
    (*untracked_seconds)[side] = 0.0f;
    if (!tracked[side]) {
      // Carried along at the tracked hand's pace (velocities measured up to the previous sample).
      const float step = static_cast<float>(t - previous_time_.value_or(t));
      position[side] = previous_position_[side] + step * TravelVelocity(1 - side) + CatchUpStep(side, t);
      guess_[side] = position[side];
      (*untracked_seconds)[side] = static_cast<float>(t - *last_tracked_time_[side]);
      lost_[side] = true;
      continue;
    }
    if (lost_[side]) {  // back: cross-fade from the guess, which goes on as if the hand were still lost
      reentry_time_[side] = t;
      lost_after_[side] = *last_tracked_time_[side];
      lost_[side] = false;
    }
    if (reentry_time_[side]) {
      const double u = (t - *reentry_time_[side]) / reentry_seconds_;
      if (u >= 1.0) {
        reentry_time_[side].reset();
      } else {
        const float step = static_cast<float>(t - previous_time_.value_or(t));
        guess_[side] += step * TravelVelocity(1 - side) + CatchUpStep(side, t);
        // Smoothstep weights, flat at both ends: position and velocity continuous with the guess
        // when the hand comes back and with the input when the fade ends.
        const float w = Smoothstep(u);
        position[side] = (1.0f - w) * guess_[side] + w * input[side];
        fading[side] = {.weight = 1.0f - w, .seconds = static_cast<float>(t - lost_after_[side])};
      }
    }
    if (!reentry_time_[side]) catch_up_[side].reset();  // the hand is its input again
    last_tracked_time_[side] = t;
  }
  for (int side = 0; side < 2; ++side) {
    auto& recent = recent_[side];
    if (!tracked[side]) {
      recent.clear();  // its velocity resumes from its own samples once it is back
      continue;
    }
    recent.emplace_back(t, input[side]);
    while (recent.size() > 2 && t - recent[1].first >= travel_seconds_) recent.pop_front();
  }
  if (fading_guess != nullptr) *fading_guess = fading;
  sample->left = position[0];
  sample->right = position[1];
  previous_time_ = t;
  previous_position_ = position;
  return true;
}

}  // namespace mocap

// While one hand's tracker has lost it, the body goes on from the other hand (issue #25 item 2):
// the lost hand travels with the body — at the tracked hand's mean velocity over the ground over
// the last `travel_seconds` (a walking body's pace; a hand moving about a standing body averages to
// little, and one raised or lowered does not lift its partner),
// from where it was last tracked — so its own swing is not invented and the tracked hand's is not
// copied. When it comes back, the guess goes on for `reentry_seconds` and the hand cross-fades
// from it to the input (smoothstep weights: position and velocity stay continuous) instead of
// stepping there in one frame. Samples whose hands are both tracked pass through unchanged once any re-entry has
// settled.
#pragma once

#include <array>
#include <deque>
#include <optional>
#include <utility>

#include <Eigen/Core>

#include "motion/reconstruct/wrist_resampler.h"

namespace mocap {

class OneHandBridge {
 public:
  explicit OneHandBridge(double reentry_seconds = 0.5, double travel_seconds = 1.0)
      : reentry_seconds_(reentry_seconds), travel_seconds_(travel_seconds) {}

  // Fills in the position of a hand `sample` does not track and eases a returning one; sets
  // `untracked_seconds` per hand (left, right) to the seconds since that hand was last tracked
  // (0: tracked) and `fading_guess` (optional) to how much of a returning hand's position is
  // still the guess. False, leaving the sample as it was, when no hand is tracked or when one is
  // not and no earlier sample tracked it (nothing to go on from): the caller drops the sample.
  bool Fill(WristSample* sample, std::array<float, 2>* untracked_seconds,
            std::array<FadingGuess, 2>* fading_guess = nullptr);
  // Moves `side`'s guess by `offset` as well, eased in over kCatchUpSeconds from the next sample
  // (smoothstep: no step in position or velocity). For a hand let go late: a device found put down
  // only after it lay still for seconds, while its person walked on (hand_rest.h).
  void Carry(int side, const Eigen::Vector3f& offset);
  static constexpr double kCatchUpSeconds = 1.0;
  // A new session: nothing is remembered.
  void Reset() { *this = OneHandBridge(reentry_seconds_, travel_seconds_); }

 private:
  // The mean velocity of `side`'s input over the ground (y = 0) over the last travel_seconds_
  // (zero before two samples).
  Eigen::Vector3f TravelVelocity(int side) const;
  // The part of a Carry offset due between the previous sample and time t (zero without one).
  Eigen::Vector3f CatchUpStep(int side, double t);

  double reentry_seconds_, travel_seconds_;
  std::array<std::optional<double>, 2> last_tracked_time_;
  std::array<bool, 2> lost_{false, false};
  std::optional<double> previous_time_;
  std::array<Eigen::Vector3f, 2> previous_position_{Eigen::Vector3f::Zero(), Eigen::Vector3f::Zero()};
  std::array<std::deque<std::pair<double, Eigen::Vector3f>>, 2> recent_;  // each hand's tracked input
  // Where a lost hand is guessed to be; after it is back, the guess goes on for the cross-fade.
  std::array<Eigen::Vector3f, 2> guess_{Eigen::Vector3f::Zero(), Eigen::Vector3f::Zero()};
  std::array<std::optional<double>, 2> reentry_time_;  // when a hand in its cross-fade came back
  std::array<double, 2> lost_after_{0.0, 0.0};         // when it was last tracked before it was lost
  struct CatchUp {
    Eigen::Vector3f offset = Eigen::Vector3f::Zero();
    std::optional<double> start;  // the first sample's time after Carry
    float applied = 0;            // the eased share of `offset` already added
  };
  std::array<std::optional<CatchUp>, 2> catch_up_;
};

}  // namespace mocap

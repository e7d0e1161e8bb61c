// Put-down detection (issue #25, tracking states): a controller or phone set down on a table
// stays still to a centimetre while the person goes on moving, which no held hand does (tremor
// and the body's sway move a held device by more than that within seconds). One detector per hand.
//
// A hand is "put down" once its input has stayed within kStillRadius of one place for
// kPutDownSeconds while the other hand travelled at least kOtherHandTravel (both still is a
// person at rest, or both devices down: nothing to tell them apart) and went kWalkedAway over the
// ground (a hand resting at the side while the other one waves is still too, and wrists alone
// cannot tell it from a device on a table beside the person: only a device the person left is
// told); it stays put down until its input leaves that place by kPickUpDistance. Sooner where the person has plainly
// walked away: a hand still for kEarlyStillSeconds while the other one, having travelled kOtherHandTravel, is further
// from it than the body's wrists can be held apart (`wrist_span`, a margin of kOutOfReachMargin) lies where no arm
// holds it.
//
// The session reads it on the raw samples and lets a put-down hand go (reconstruction_session.h):
// the body goes on from the other hand, the put-down one carried with it as a lost hand is.
#pragma once

#include <deque>

#include <Eigen/Core>

namespace mocap {

inline constexpr double kPutDownSeconds = 2.5;
inline constexpr float kStillRadius = 0.015f;     // metres
inline constexpr float kOtherHandTravel = 0.15f;  // metres, path length over the window
inline constexpr float kWalkedAway = 0.5f;        // metres over the ground, across the window
inline constexpr float kPickUpDistance = 0.03f;   // metres
inline constexpr double kEarlyStillSeconds = 0.5;
inline constexpr float kOutOfReachMargin = 1.1f;  // as for an input out of an arm's reach

// How long a hand has stayed within kStillRadius of one place, sample by sample (no window kept):
// a cheap first sign of a device put down, for what must not wait for HandRestDetector.
class StillHand {
 public:
  // Seconds the hand has been still up to `time` (0 when it just moved).
  double Update(const Eigen::Vector3f& position, double time) {
    if (!seen_ || (position - place_).norm() > kStillRadius) {
      place_ = position;
      since_ = time;
      seen_ = true;
    }
    return time - since_;
  }
  void Forget() { seen_ = false; }

 private:
  Eigen::Vector3f place_ = Eigen::Vector3f::Zero();
  double since_ = 0.0;
  bool seen_ = false;
};

class HandRestDetector {
 public:
  // `wrist_span`: the body's (WristSpan, metres); 0 leaves out the sooner rule.
  explicit HandRestDetector(float wrist_span = 0.0f) : wrist_span_(wrist_span) {}
  // One frame's input of this hand and the other; true while this hand is put down.
  bool Update(double time, const Eigen::Vector3f& hand, const Eigen::Vector3f& other_hand);
  // A frame where either hand is a guess (lost, bridged across a dropout, still fading back in):
  // no evidence either way. A still run starts again after it; a hand already put down stays
  // so (a tracker that briefly lost a device lying on a table finds it where it was).
  bool Unobserved() {
    window_.clear();
    return put_down_;
  }
  bool put_down() const { return put_down_; }
  // The other hand's displacement over the ground (y = 0) across the still run that put this one
  // down: how far the person has gone since the device was set down, before anyone could tell.
  const Eigen::Vector3f& other_travel_since_set_down() const { return other_travel_; }

 private:
  struct Sample {
    double time;
    Eigen::Vector3f hand, other;
  };
  // Puts the hand down at `place`, the other hand having gone from `other_then` meanwhile.
  void SetDown(const Eigen::Vector3f& place, const Eigen::Vector3f& other_then, const Eigen::Vector3f& other_now);

  float wrist_span_ = 0.0f;
  std::deque<Sample> window_;  // the last kPutDownSeconds
  bool put_down_ = false;
  Eigen::Vector3f rest_place_ = Eigen::Vector3f::Zero();
  Eigen::Vector3f other_travel_ = Eigen::Vector3f::Zero();
};

}  // namespace mocap

// Put-down detection (issue #25, tracking states): a controller or phone set down on a table
// stays still to a centimetre while the person goes on moving, which no held hand does (tremor
// and the body's sway move a held device by more than that within seconds). One detector per hand.
//
// A hand is "put down" once its input has stayed within kStillRadius of one place for
// kPutDownSeconds while the other hand travelled at least kOtherHandTravel (both still is a
// person at rest, or both devices down: nothing to tell them apart); it stays put down until its
// input leaves that place by kPickUpDistance.
#pragma once

#include <deque>

#include <Eigen/Core>

namespace mocap {

inline constexpr double kPutDownSeconds = 2.5;
inline constexpr float kStillRadius = 0.015f;     // metres
inline constexpr float kOtherHandTravel = 0.15f;  // metres, path length over the window
inline constexpr float kPickUpDistance = 0.03f;   // metres

class HandRestDetector {
 public:
  // One frame's input of this hand and the other; true while this hand is put down.
  bool Update(double time, const Eigen::Vector3f& hand, const Eigen::Vector3f& other_hand);
  // A frame where either hand is a guess (lost, bridged across a dropout, still fading back in):
  // no evidence either way. A still run starts again after it; a hand already put down stays
  // so (a tracker that briefly lost a device lying on a table finds it where it was).
  bool Unobserved() {
    window_.clear();
    return put_down_;
  }

 private:
  struct Sample {
    double time;
    Eigen::Vector3f hand, other;
  };
  std::deque<Sample> window_;  // the last kPutDownSeconds
  bool put_down_ = false;
  Eigen::Vector3f rest_place_ = Eigen::Vector3f::Zero();
};

}  // namespace mocap

#pragma once

// How low a hand, and the body, can go (issues #22 and #25). The session's space has the ground at y = 0 (the
// input is converted to it on the way in, docs/input-conventions.md), so input under it is a
// tracker's drift or a floor declared too high, never a hand.

namespace mocap {

// The lowest a wrist joint is: over a hand lying flat on the floor.
inline constexpr float kLowestWristHeight = 0.03f;

// Input further than this under the ground (after A2's smoothing, so a tracker's jitter about a
// hand on the floor does not flicker) is out of the body's reach: the hand stops at the floor.
inline constexpr float kUnderFloorTolerance = 0.02f;

// The lowest the A6 solve puts a joint the body rests on when it is down (BodyModel's floor
// joints): a limb's radius for pelvis, shoulders, elbows, hips and knees, half a head for the head.
inline constexpr double kLowestJointHeight = 0.03;
inline constexpr double kLowestHeadHeight = 0.08;

}  // namespace mocap

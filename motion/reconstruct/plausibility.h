// Plausibility of a reconstructed body without ground truth (issue #22): how fast the output moves
// against the fastest the database's own bodies move, how far the hands are from the input they
// were given, how high the lower foot is and whether anything goes under the floor.
//
// MotionLimits are measured once, when a ReconstructionDatabase is built, from its clips' captured
// motion; the session's motion guard (motion_guard.h) keeps the output within them, and the
// measures below (used by mocap-eval and by `mocap reconstruct`'s summary) report against them.
// Everything is in metres and seconds, Y up, ground at y = 0.
#pragma once

#include <algorithm>
#include <array>
#include <map>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "motion/preprocess/frame_features.h"
#include "motion/skeleton/body_topology.h"
#include "motion/skeleton/skeleton.h"

namespace mocap {

// The windows over which the hands' motion bounds the body's (MotionLimits): the first long
// enough that an arm's swing or wave averages out, short enough to follow a start or a stop; the
// second long enough that a standing body's gestures (within an arm's reach) average to little.
inline constexpr std::array<double, 2> kHandsWindowsSeconds = {0.5, 2.0};
inline constexpr double kHandsWindowSeconds = kHandsWindowsSeconds[0];
// The hands stand while their midpoint's mean ground speed over the last kStandingWindowSeconds is
// below kStandingHandsSpeed (MotionGuardOptions' defaults; MotionLimits::pelvis_speed_while_hands_stand).
inline constexpr double kStandingWindowSeconds = 1.0;
inline constexpr float kStandingHandsSpeed = 0.25f;  // m/s
// Frames of window `w` of kHandsWindowsSeconds (at least 1).
int HandsWindowFrames(double frame_time, int w = 0);

// How fast the database's bodies move (its captured clips, consecutive frames of one clip only).
// Speeds are finite differences of world positions, accelerations second differences.
struct MotionLimits {
  float pelvis_speed_p99 = 0, pelvis_speed_max = 0;                // m/s
  float pelvis_acceleration_p99 = 0, pelvis_acceleration_max = 0;  // m/s²
  // How much faster the pelvis moves than the wrists' midpoint has moved on average over the last
  // kHandsWindowSeconds (a body does not run off while both hands stay put): the largest
  // |pelvis velocity| − |midpoint displacement over the window| / window, m/s.
  float pelvis_speed_beyond_hands_max = 0;
  // Per window of kHandsWindowsSeconds: how fast the pelvis moved while the hands' midpoint
  // moved (its mean speed over that window) at most as fast as bin i's top, bins kHandsSpeedBin
  // wide: the bin's 99.99th percentile, its fastest if it has fewer than 10,000 frames (a
  // running maximum: never decreasing; docs/method.md A7). Tighter than hands + pelvis_speed_beyond_hands_max
  // where the hands move a little: that sum lets every gesture of a standing body move it as fast
  // as the database's fastest start does.
  static constexpr float kHandsSpeedBin = 0.1f;  // m/s
  std::array<std::vector<float>, kHandsWindowsSeconds.size()> pelvis_speed_by_hands_speed;
  // The fastest the pelvis may move while the hands' mean speeds over the windows are
  // `hands_speed` (m/s): the smallest of the bounds above, each of which all but the bins'
  // outliers keep (past a window's last bin, that window's bound is the sum, or none).
  float PelvisSpeedBoundForHands(const std::array<float, kHandsWindowsSeconds.size()>& hands_speed) const;
  // The same for the faster ankle (a foot swings faster than the body it carries): per window, how
  // fast it moved while the hands moved as slowly as bin i's top; past a window's last bin, the
  // fastest ankle.
  std::array<std::vector<float>, kHandsWindowsSeconds.size()> ankle_speed_by_hands_speed;
  float AnkleSpeedBoundForHands(const std::array<float, kHandsWindowsSeconds.size()>& hands_speed) const;
  // How fast the pelvis moved while the hands stood (their midpoint's mean ground speed over the
  // last kStandingWindowSeconds below kStandingHandsSpeed): the 99.99th percentile, the fastest
  // with fewer than 10,000 such frames; 0 with none. The tail above it is bodies that set off
  // before their hands travel; a stream's body that does the same is held to it until the hands
  // show the walk (MotionGuard), a standing body's solve that hops is held always.
  float pelvis_speed_while_hands_stand = 0;
  float wrist_speed_max = 0;                                     // either wrist, m/s
  float ankle_speed_max = 0;                                     // either ankle, m/s
  float wrist_acceleration_p99 = 0, wrist_acceleration_max = 0;  // either wrist, m/s²
  bool valid() const { return pelvis_speed_max > 0; }
};

// `clips`: each clip's A1 features (frame_features.h), consecutive frames `frame_time` apart.
// All zero when no clip has two frames.
MotionLimits MeasureMotionLimits(std::span<const std::span<const FrameFeatures>> clips, double frame_time);

// Where a pose's measured points are, read from its joints' world positions.
struct PlausibilityRig {
  int pelvis = -1;
  std::array<int, 2> wrists{-1, -1}, ankles{-1, -1}, shoulders{-1, -1};
  std::array<float, 2> arm_reach{};  // shoulder to wrist with the arm straight, metres
  std::vector<int> body_joints;      // joints that can touch the floor (all but those above the pelvis)
};
// `skeleton` offsets in metres. Shoulders: the landmarks, else the wrist's grandparent's parent.
PlausibilityRig MakePlausibilityRig(const Skeleton& skeleton, const BodyLandmarks& landmarks);

// One output frame as the measures see it.
struct PlausibilityFrame {
  double time = 0;  // seconds
  int segment = 0;  // accelerations are measured within a segment only
  Eigen::Vector3f pelvis = Eigen::Vector3f::Zero();
  // input: the wrists the frame was given (Eigen's vectors are not zeroed by {}: spelled out).
  std::array<Eigen::Vector3f, 2> hands{Eigen::Vector3f::Zero(), Eigen::Vector3f::Zero()};
  std::array<Eigen::Vector3f, 2> input{Eigen::Vector3f::Zero(), Eigen::Vector3f::Zero()};
  std::array<Eigen::Vector3f, 2> ankles{Eigen::Vector3f::Zero(), Eigen::Vector3f::Zero()};
  std::array<bool, 2> input_in_reach{true, true};  // input within the arm's reach of the shoulder, not under the floor
  float lowest_point = 0;                          // lowest body joint, m above the ground
  bool flagged = false;                            // the engine flagged the frame's input implausible
  bool motion_limited = false;                     // the engine's motion guard held the pelvis back
  int put_down_hands = 0;                          // hands the engine said were put down (hand_rest.h)
};
// `joints`: world positions of every joint of the rig's skeleton.
PlausibilityFrame MakePlausibilityFrame(const PlausibilityRig& rig, std::span<const Eigen::Vector3f> joints,
                                        const std::array<Eigen::Vector3f, 2>& input, double time, int segment,
                                        bool flagged, bool motion_limited);

// Counts of non-negative values in bins of `bin_width` (sparse: only the bins used are stored);
// quantiles to the bin's top, never past the largest value added.
class Histogram {
 public:
  explicit Histogram(float bin_width = 0.001f) : bin_width_(bin_width) {}
  void Add(float value);
  void Merge(const Histogram& other);  // same bin width
  long count() const { return count_; }
  float Quantile(double q) const;  // 0 when empty
  // The share of values below `value` (to the bin: values in the bin holding `value` count as
  // below); 1 when empty.
  double FractionBelow(float value) const;
  float max() const { return max_; }

 private:
  float bin_width_;
  std::map<long, long> bins_;
  long count_ = 0;
  float max_ = 0;
};

// Sums and extremes over frames; Merge() combines clips.
struct PlausibilityStats {
  long frames = 0;
  Histogram pelvis_speed{0.01f};      // m/s, per frame after a segment's first
  float pelvis_acceleration_max = 0;  // m/s²
  long frames_over_speed_limit = 0;   // pelvis faster than the `speed_limit` given to Measure
  Histogram ankle_speed{0.01f};       // m/s, per ankle and frame after the first (a foot teleports too)
  Histogram hand_distance{0.001f};    // m, per hand-frame with the input in reach
  long hand_frames_out_of_reach = 0;  // reported apart
  float hand_distance_out_of_reach_max = 0;
  Histogram lower_foot_height{0.001f};  // lower ankle above the planted ankle height (≥ 0), m
  float penetration_max = 0;            // deepest body joint below the ground, metres
  long penetrating_frames = 0;          // frames with a body joint more than 1 cm under the ground
  long flagged_frames = 0;
  long motion_limited_frames = 0;
  long put_down_hand_frames = 0;  // hand-frames said put down

  void Merge(const PlausibilityStats& other);
};

// Measures `frames` (one reconstruction, in output order). `planted_ankle_height`: the ankle
// height of a foot on the ground (ReconstructionDatabase::planted_ankle_height()); `speed_limit`:
// the speed frames_over_speed_limit counts past (m/s; 0 = count none).
PlausibilityStats MeasurePlausibility(std::span<const PlausibilityFrame> frames, float planted_ankle_height,
                                      float speed_limit);

// The issue #22 bound for a point of a clip's body (its pelvis, an ankle) that the capture moves at
// most `own_max_speed` (m/s): the output's may move at most max(2 × own, own + 1 m/s).
inline float AllowedSpeed(float own_max_speed) { return std::max(2.0f * own_max_speed, own_max_speed + 1.0f); }

}  // namespace mocap

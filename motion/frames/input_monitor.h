// Floor calibration and plausibility checks of a session's input (issue #12): what cannot be
// right in a caller's declared frame is said, with what looks wrong, instead of being
// reconstructed silently.
//
// Samples enter in native axes and metres (FrameTransform), the declared floor already
// subtracted unless the floor is calibrated. Thresholds come from body proportions, with H the
// performer's height (SessionConfig.performer_height, else the database performer's):
// - floor calibration: the median over the first `window_seconds` of the lower wrist's height is
//   taken as kWristHangFraction · H above the floor (a performer standing or walking with at least
//   one arm hanging; 0.474 over the walks and runs of the held-out bandai-namco-2 clips, 0.466
//   over the others, tests/motion/frames; anthropometric tables give 0.485 for a wrist hanging at
//   rest). Samples are held
//   until the window is full, so the first frames leave up to `window_seconds` later.
// - units (first window): the wrists' median distance below kMinWristSeparationFraction · H
//   (two wrist joints cannot come closer than the hands' thickness) names the unit that would make
//   it a body's: "metres declared as centimetres?". Too far apart is refused per sample
//   (WristSeparationProblem).
// - floor (first window, declared floors only): the lower wrist's median height below
//   −kBelowFloorFraction · H ("wrists below the floor"), or above kAboveFloorFraction · H (both
//   wrists higher than a raised hand reaches: the floor is too low).
// - sides (whole session): while the body travels (the wrists' midpoint moving faster than
//   kTravelSpeed over ~0.5 s), the left wrist is on the left of the travel direction, unless the
//   body walks backwards. Walking forwards, the wrist ahead of the body swings higher than the
//   one behind (the elbow bends on the forward swing), so the smoothed product of the wrists'
//   lead along the travel and their height difference (label-free) says which way the body
//   faces; a vote for "swapped" needs it to say forwards (at least kMinForwardEvidence of its
//   magnitude) or a pace nobody walks backwards (kBackwardsWalkSpeed). When at least
//   kSwapVoteShare of kSwapVotes consecutive votes (one per 0.1 s, each with the wrists at least
//   kMinSideOffsetFraction · H apart across the travel) say swapped: "left and right look
//   swapped" (or a mirrored frame: the handedness declared wrong). Standing still says nothing:
//   a mirrored pair of wrists at rest is another pose's. On bandai-namco-1 no correct walk,
//   backwards walk or side step is said swapped, and 50 of its 60 forward walks, runs and dashes
//   are when swapped (tests/motion/frames/held_out_input_test.cc).
// - up axis: the first window's lower wrist along the declared up axis at the floor (below
//   kUpAxisFloorFraction · H) while another axis holds it at hanging height (kHangBand · H, the
//   floor at 0 on it): "Z up declared as Y up?"; below or far above the floor, that axis is named
//   in the floor warning as the other possible cause. Over
//   the whole session, the wrists' midpoint rising or sinking more than kVerticalTravelFraction · H
//   within kVerticalTravelSeconds (faster than anyone climbs stairs): the body travels along the
//   declared up axis, which is then a horizontal one.
//
// Thread safety: none; one session's caller at a time.
#pragma once

#include <array>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "motion/frames/frame_convention.h"
#include "motion/reconstruct/wrist_resampler.h"

namespace mocap {

inline constexpr float kDefaultBodyHeight = 1.7f;  // metres, when none is known
inline constexpr float kWristHangFraction = 0.47f;
inline constexpr float kMinWristSeparationFraction = 0.02f;
inline constexpr float kBelowFloorFraction = 0.05f;
inline constexpr float kAboveFloorFraction = 1.1f;
inline constexpr float kTravelSpeed = 0.4f;  // m/s
inline constexpr float kMinSideOffsetFraction = 0.03f;
inline constexpr float kFacingSmoothing = 0.05f;    // per look (0.1 s): two gait cycles' memory
inline constexpr float kMinForwardEvidence = 0.5f;  // of the smoothed lead · rise against its magnitude
inline constexpr float kBackwardsWalkSpeed = 2.0f;  // m/s: the walk-to-run transition; faster is a run, forwards
inline constexpr int kSwapVotes = 15;
inline constexpr float kUpAxisFloorFraction = 0.15f;
inline constexpr float kHangBand[2] = {0.3f, 0.75f};
inline constexpr float kVerticalTravelFraction = 1.5f;
inline constexpr double kVerticalTravelSeconds = 4.0;
inline constexpr float kSwapVoteShare = 0.8f;

struct InputWarning {
  enum class Kind { kUnits, kBelowFloor, kAboveFloor, kSwapped, kUpAxis };
  Kind kind;
  std::string message;
};

struct InputMonitorOptions {
  float body_height = kDefaultBodyHeight;  // H, metres
  double window_seconds = 1.0;             // floor calibration and the first checks read this much input
};

// A sample on its way to the session, with its position in the caller's stream.
struct MonitoredSample {
  WristSample sample;
  long index = 0;
};

class InputMonitor {
 public:
  // `convention` names the caller's unit in messages; `calibrate_floor` holds samples until the
  // window is full and subtracts the estimated floor from every sample.
  InputMonitor(const FrameConvention& convention, bool calibrate_floor, const InputMonitorOptions& options);

  // Appends to `ready` the samples that may go on (all of them, except while calibrating), and to
  // `warnings` what the checks found (each kind at most once per session).
  void Add(const WristSample& sample, long index, std::vector<MonitoredSample>* ready,
           std::vector<InputWarning>* warnings);
  // End of input: a window not yet full is judged (and calibrated) on what it holds.
  void Finish(std::vector<MonitoredSample>* ready, std::vector<InputWarning>* warnings);

  // The first window has been judged (the floor is known).
  bool window_done() const { return window_done_; }
  // The native height of the floor the monitor estimated (metres; 0 without calibration).
  float calibrated_floor() const { return calibrated_floor_; }

 private:
  void CloseWindow(std::vector<MonitoredSample>* ready, std::vector<InputWarning>* warnings);
  // Both trackers below, on a sample whose hands are both tracked.
  void Track(const WristSample& sample, std::vector<InputWarning>* warnings);
  void TrackSides(const WristSample& sample, std::vector<InputWarning>* warnings);
  void TrackHeight(const WristSample& sample, std::vector<InputWarning>* warnings);
  // The caller's name ("+Z") of the native axis `index` (0 X, 2 Z) with `sign`.
  std::string CallerAxisName(int index, float sign) const;
  // The caller's name of another axis that holds the first window's wrists at hanging height.
  std::optional<std::string> UpAxisHoldingHangingWrists() const;

  FrameConvention convention_;
  bool calibrate_floor_;
  InputMonitorOptions options_;
  bool window_done_ = false;
  float calibrated_floor_ = 0.0f;
  std::optional<double> first_time_;
  std::vector<MonitoredSample> window_;  // the first window's samples (held while calibrating)
  // Sides: the wrists' midpoint every ≥ 0.1 s, the last kWaypoints of them.
  static constexpr int kWaypoints = 6;
  struct Waypoint {
    double time;
    Eigen::Vector3f middle;
  };
  std::array<Waypoint, kWaypoints> waypoints_{};
  int waypoint_count_ = 0;
  int votes_ = 0, swapped_votes_ = 0;
  // Smoothed (leading wrist's lead along the travel) × (its height above the other), and |…|.
  float facing_evidence_ = 0.0f, facing_scale_ = 0.0f;
  bool swap_reported_ = false;
  // Up axis: the wrists' midpoint every ≥ 0.2 s over the last kVerticalTravelSeconds.
  std::deque<Waypoint> heights_;
  bool up_axis_reported_ = false;
};

// A message when two wrists `separation_metres` apart (as declared) are not one person's: more
// than kMaxWristSeparationMetres, naming the unit that would make them plausible ("wrist samples
// 180 units apart: centimetres declared as metres?"). nullopt when plausible.
inline constexpr double kMaxWristSeparationMetres = 3.0;
std::optional<std::string> WristSeparationProblem(double separation_metres, LengthUnit declared);

}  // namespace mocap

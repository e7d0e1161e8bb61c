// The last step of every reconstruction (issue #22, "never teleport"): the body moves only as the
// database's bodies move. MotionGuard follows the solved pelvis while it moves as a body can, and
// otherwise approaches it with bounded speed and acceleration (a body that the solve put 1 m away
// in one frame walks there instead), and no faster than its hands allow (when the hands' midpoint
// stays put, so does the body: a standing user's avatar does not run off); InputJumpDetector says when a hand's input
// does what no hand does (a controller's 20 cm step in one frame, a tracker that repeats samples and then jumps).
//
// The bounds are the database's own (MotionLimits, measured when it is built) times margins: no
// constant here comes from a test set. Causal and allocation-free, so every mode (fixed lag, sub-
// intervals, whole clip) runs it the same way on the frames it emits, in order.
#pragma once

#include <array>
#include <limits>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "motion/core/recent_values.h"
#include "motion/reconstruct/plausibility.h"

namespace mocap {

struct MotionGuardOptions {
  bool enabled = true;
  // Pelvis bounds: the database's fastest pelvis speed and acceleration, and the fastest its
  // pelvis moved while its hands moved as slowly as the input's (MotionLimits::
  // PelvisSpeedBoundForHands), times these margins (room for performers a little faster than the
  // database's and for the solve's own jitter).
  float speed_margin = 1.25f;
  float acceleration_margin = 1.5f;
  float beyond_hands_margin = 1.0f;
  // A hand's input is implausible when it is faster than `input_speed_margin` × the database's
  // fastest wrist, or accelerates faster than `input_acceleration_margin` × its fastest.
  float input_speed_margin = 1.25f;
  float input_acceleration_margin = 1.25f;
  // A tracker's own noise is no motion: its share of a frame's speed and acceleration is allowed
  // beside those bounds, `input_noise_sigmas` times its spread, measured from the hand's observed
  // input over the last `input_noise_window_seconds` (InputJumpDetector). 0 sigmas = none.
  float input_noise_sigmas = 5.0f;
  float input_noise_window_seconds = 1.0f;
  // While the hands' midpoint stays put over the ground (its mean ground speed over the hands'
  // window below `standing_hands_speed`), the pelvis follows the solve through an exponential
  // filter of this time constant; the filter fades out linearly up to `moving_hands_speed`. A
  // standing body's solve hops between the stances of its neighbours (1-3 cm a frame, output
  // pelvis speeds of 1-3 m/s on bows, waves and swordplay whose capture stands), which a body that
  // stands does not do; a walking body's pelvis is left as solved. 0 = off.
  float standing_smoothing_seconds = 0.1f;
  float standing_hands_speed = kStandingHandsSpeed, moving_hands_speed = 0.6f;
  // The window of that mean ground speed.
  float standing_window_seconds = static_cast<float>(kStandingWindowSeconds);
  // While the hands stand so, the pelvis is also no faster than the database's pelvis moved while
  // its hands stood (MotionLimits::pelvis_speed_while_hands_stand, × beyond_hands_margin as the
  // other bounds by the hands), that bound fading into the
  // others as the standing filter fades. A standing body's solve hops 10-20 cm a frame between its
  // neighbours' stances; the filter passed a quarter of that, and the bound by the hands' speed let
  // through what a body starting to walk does (up to 1.2 m/s while a still capture allows 1.05:
  // docs/evaluation.md stop 85). False: the bounds by the hands' speed alone.
  bool bound_standing_body = true;
  // A noisier tracker makes a standing body's solve hop further (phone AR's 2-3 cm of jitter:
  // the pelvis of standing gestures went faster than their capture allows in a quarter of the
  // development split's clips at lag 0): above `standing_noise_acceleration` of input noise (the
  // spread per axis of its second differences, m/s², as InputJumpDetector measures it; 25 is
  // 1.1 cm of white noise at 30 frames/s, twice the development input's) the filter's time
  // constant grows in proportion, up to `standing_noise_max_factor` times. 1 = never.
  float standing_noise_acceleration = 25.0f;
  float standing_noise_max_factor = 2.0f;
  // A stream's first frames know the least: its first solves hop between neighbours' stances
  // (raise-ups and waves of the standard split went 1.2-2.6 m/s in their first 0.2 s, causally)
  // while the hands' windows hold a few frames. Over its first `start_ease_seconds` the body
  // eases in through the standing filter, fading linearly: fully where the hands ahead are not
  // known (lag 0), else as far as they stand over the span known (SetLeadingHands). 0 = off.
  float start_ease_seconds = 0.2f;
  // Until a stream has run this long, whether its hands stand is read as if they had stood where
  // they were first seen before it began (a live user starts still): their ground travel so far,
  // or ahead where the input ahead spans longer, over this span at least. Over the few frames so
  // far, the arms of a raise-up or a wave (0.3-1.6 m/s forward) read as a walk while the first
  // solves of a body of the wrong size lurched 10-45 cm towards hands it could not reach yet
  // (issue #22, docs/evaluation.md stop 81). Not where the input ahead spans this long (a whole
  // clip): it says whether the hands travel. 0 = the frames so far.
  double start_rest_seconds = 0.5;
};

class MotionGuard {
 public:
  MotionGuard(const MotionLimits& limits, double frame_time, const MotionGuardOptions& options);

  // The next output frame at `time` (seconds, increasing; a gap counts as its length): `solved`
  // is where the solve put the pelvis, `hands` the midpoint of the input wrists (world metres).
  // Returns where the pelvis goes; `*limited` is set when that is not the solve's place (eased
  // while standing) by more than 1 mm.
  Eigen::Vector3f Next(double time, const Eigen::Vector3f& solved, const Eigen::Vector3f& hands, bool* limited);
  void Reset() { has_previous_ = false; }

  // Where the input ahead is known when a stream starts (a whole clip, a window of one): how far
  // the hands' midpoint went from the stream's first frame over the shorter window of
  // kHandsWindowsSeconds (or over the input there is, if shorter). Until that window has filled,
  // the hands' mean speed over it is read over this span rather than over the few frames so far:
  // two frames of a tracker's jitter are no walk. Read by the next Next if it starts a stream (the
  // first, or a new clock); ignored if the stream goes on.
  void SetLeadingHands(double seconds, const Eigen::Vector3f& displacement);
  // The input's noise as InputJumpDetector measures it (the noisier hand's, m/s²; 0 = not yet
  // measured), read by the standing filter from the next Next on.
  void SetInputNoise(float acceleration_noise) { input_noise_ = acceleration_noise; }

  float speed_limit() const { return speed_limit_; }
  // After Next: how far the standing filter held the body as standing (1: the hands stood, 0:
  // they travel, or no standing filter), the stream's first frames' ease included.
  float standing() const { return standing_; }
  // After Next: the pelvis's velocity into the frame it returned (m/s; zero on a stream's first
  // frame) and the fastest it could have gone there (m/s; infinite on a stream's first frame,
  // whose speed is not known). What moves the body after the guard keeps within the same bound
  // (ReachLean::Shift).
  const Eigen::Vector3f& velocity() const { return previous_velocity_; }
  float speed_bound() const { return speed_bound_; }
  // After Next: the fastest either foot may move into that frame (m/s; infinite on a stream's
  // first frame): the database's ankles' bound for hands that move as these do
  // (MotionLimits::AnkleSpeedBoundForHands), with the margins of the pelvis' bounds.
  float foot_speed_bound() const { return foot_speed_bound_; }

 private:
  double frame_time_;
  float speed_limit_, acceleration_limit_;
  float standing_speed_limit_;                                  // the pelvis's while the hands stand (infinite: none)
  float speed_bound_ = std::numeric_limits<float>::infinity();  // the last Next's
  float standing_ = 0.0f;                                       // the last Next's
  float foot_speed_bound_ = std::numeric_limits<float>::infinity();  // the last Next's
  MotionLimits hands_limits_;  // only the bounds by the hands' speed and the ankles' are read, margins applied
  float standing_smoothing_seconds_, standing_hands_speed_, moving_hands_speed_, standing_window_seconds_,
      start_ease_seconds_;
  double start_rest_seconds_;
  float standing_noise_acceleration_, standing_noise_max_factor_, input_noise_ = 0.0f;
  std::array<int, kHandsWindowsSeconds.size()> bound_window_frames_;  // the windows of the speed bound
  bool has_previous_ = false, has_velocity_ = false;
  double previous_time_ = 0;
  Eigen::Vector3f previous_output_ = Eigen::Vector3f::Zero(), previous_target_ = Eigen::Vector3f::Zero(),
                  previous_velocity_ = Eigen::Vector3f::Zero();
  // The hands' midpoint over the last frames of the current stretch without a gap, as many as the
  // longer of the two windows (a ring, sized once).
  struct HandsSample {
    double time;
    Eigen::Vector3f midpoint;
  };
  RecentValues<HandsSample> hands_;
  struct LeadingSpan {
    double seconds;
    Eigen::Vector3f displacement;
  };
  std::optional<LeadingSpan> pending_leading_, leading_;  // given for the next stream; this stream's
  double stream_start_ = 0;
};

// Flags input samples no hand could produce, from the resampled input's last three frames: a
// step faster, or a change of velocity harder, than the database's hands make, beyond what the
// tracker's own noise adds. A tracker's jitter alone moves a still hand: white noise of σ per
// axis gives second differences of √6·σ per axis, at 30 frames/s and σ = 2.5 cm (phone AR) 55
// m/s², the hardest a whole Bandai walk database's hands accelerate being 19 (its fastest dance
// far more). So each hand's noise is measured as it comes, robustly: the median norm of its
// second differences over the last `input_noise_window_seconds` of observed input (a 3-D normal's
// norm has median 1.538 σ), which a jump, a frame or two of them, does not move; its share of a
// step, `input_noise_sigmas` times its spread, is allowed beside each bound (in quadrature: a hand
// at its hardest and the noise at its furthest, both rare, rarely meet). Nothing is judged
// before a hand's first few observed frames have measured it.
class InputJumpDetector {
 public:
  InputJumpDetector(const MotionLimits& limits, double frame_time, const MotionGuardOptions& options);
  // `before_previous`, `previous`, `current`: one wrist's (`side`, 0 left, 1 right) input at three
  // consecutive frames (nullptr when the segment has not reached back that far). True when the
  // step into `current` is implausible, judged against the noise measured before it. `observed`:
  // the input is the device's (not a guess over a dropout): it then joins the noise measure.
  bool Step(int side, const Eigen::Vector3f* before_previous, const Eigen::Vector3f* previous,
            const Eigen::Vector3f& current, bool observed);
  // The spread of the hand's noise per axis, as the acceleration it adds (m/s²); 0 until a few
  // frames are observed.
  float AccelerationNoise(int side) const;

 private:
  float rate_, speed_limit_, acceleration_limit_, sigmas_;
  // Per hand, the norms of the last observed second differences (m/s²).
  std::array<RecentValues<float>, 2> noise_;
  mutable std::vector<float> scratch_;  // the median's copy, sized once
};

// Where a planted foot goes when the guard moves the body by `body_offset`: nowhere while the
// leg can bend for it (`leg_give` metres), and beyond that by the part of the offset past it, so
// the foot never steps as the offset crosses the bound (issue #25: all or nothing at the bound
// stepped the feet by up to `leg_give` between frames).
Eigen::Vector3f PlantedFootOffset(const Eigen::Vector3f& body_offset, float leg_give);

// The guard's rigid move of the body, no lower than the joints it rests on allow:
// `floor_clearance` is how far the lowest of them is above the floor (BodyModel::FloorClearance;
// negative when one is already under). Down by at most that much, never further down from under
// the floor; up and over the ground as it is. A body the guard held back while the solve rose
// from the floor went under it (a knee 5 cm under on `dance-short` at lag 5; stop 73).
Eigen::Vector3f OffsetAboveFloor(const Eigen::Vector3f& body_offset, float floor_clearance);

}  // namespace mocap

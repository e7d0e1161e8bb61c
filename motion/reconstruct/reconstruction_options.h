// Every parameter of the reconstruction (docs/method.md A2–A7); the defaults are the patent's where it
// gives one, otherwise what measured best (see docs/evaluation.md, mocap-eval).
#pragma once

#include "motion/reconstruct/ankle_path.h"
#include "motion/reconstruct/footskate_cleanup.h"
#include "motion/reconstruct/motion_guard.h"
#include "motion/reconstruct/pose_solver.h"
#include "motion/reconstruct/reach_lean.h"
#include "motion/reconstruct/unfamiliar_prior.h"
#include "motion/reconstruct/wrist_smoother.h"

namespace mocap {

enum class ReconstructionMethod {
  kFull,              // A2–A7: estimated ankles, then the pose model driven by wrists and ankles
  kWristsOnly,        // baseline: the A5/A6 pose model driven by the wrists alone (patent §5)
  kNearestNeighbour,  // baseline: the database pose nearest by eq. 2 (a plain motion-matching lookup)
  kNearestAverage,    // baseline: the mean of the `average_neighbours` poses nearest by eq. 2
};

enum class StreamMode {
  kSubInterval,  // A4 §3.3.1: windows of `window` frames (0 = the whole segment, i.e. offline)
  kFixedLag,     // frame t−`lag` is emitted when frame t arrives (0 = causal)
};

struct ReconstructionOptions {
  ReconstructionMethod method = ReconstructionMethod::kFull;
  StreamMode mode = StreamMode::kSubInterval;
  int window = 0;  // L, frames
  int lag = 0;     // D, frames
  // Whole-segment mode (window 0) holds every frame's ankle cloud (~64 kB per frame at K1 = 1000)
  // until the segment ends. A positive cap solves the held frames as one window once it is reached
  // (the next window starts from its last node, §3.3.1), bounding memory; 0 = no cap (offline).
  int max_window_frames = 0;

  WristSmoothingOptions smoothing;  // A2: local linear fit, σ 1 frame, 2 ahead (s = 0.5: the patent's filter)
  // A3: K1. The patent's 1000; 500 measures the same with the A4 data term (mocap-eval
  // --dev-split: MPJPE 2.382 vs 2.381 cm) at half the A3/A4 cost.
  int ankle_candidates = 500;
  AnklePathOptions ankle_path;  // A4: β, sliding rule, Gaussian σ
  // A5: K2. The patent's 200 makes a blurred local model (its mean is the average of 200 poses);
  // 50 measured best with 25 (--dev-split MPJPE 2.38 → 2.29 cm; 25: 2.27 but more jitter).
  int pose_neighbours = 50;
  int pose_components = 6;  // A5: D'
  // A5: the K2 examples weighed by a Gaussian kernel on their eq. 8 distance, of variance this ×
  // the median neighbour's squared distance (local_pose_model.h NeighbourKernelWeights); 0 = alike
  // (the patent's). Stop 84, --dev-split whole clip: 0 / 0.5 / 0.25 / 0.1 / 0.05 / 0.02 → MPJPE
  // 1.9482 / 1.9356 / 1.9222 / 1.9005 / 1.9112 / 1.9558 cm (docs/method.md A5).
  float pose_neighbour_kernel = 0.1f;
  int average_neighbours = 10;  // the kNearestAverage baseline's K
  PoseSolverOptions solver;     // A6: energy weights, LM
  // A6: the prior weight rises in a session unlike the database (unfamiliar_prior.h).
  UnfamiliarPriorOptions unfamiliar_prior;
  FootskateOptions footskate;          // A7: contacts, leg IK
  float joint_smoothing_sigma = 1.0f;  // A7: the joint-space filter's σ, frames (0 = none)
  // A7: in a whole clip (window 0: the output waits for the whole input anyway) the joint filter
  // is a sharp low-pass with the Gaussian's cutoff (low_pass_kernel.h) instead of the Gaussian:
  // the motion below the cutoff passes and the jitter above it does not. Sub-intervals and fixed
  // lags keep the Gaussian: a sharp filter needs 8σ of look-ahead, which would be their latency.
  bool joint_low_pass = true;
  // A7: where the Gaussian joint filter has no solved frame ahead of the one it emits (lag 0, a
  // stream's last frame), the pelvis takes the line fitted through the frames there are with the
  // kernel's weights (local linear regression, as A2 fits the wrists) instead of that frame
  // repeated for the taps ahead, which held a moving body a third of a frame back (σ = 1; 1.5 cm
  // at walking pace, 30 frames/s). Stop 86 (docs/method.md A7): standard split lag 0 2.6139 →
  // 2.4503 cm. With frames ahead the repeat lags by 1/20 frame or less and the line's tilt only
  // carries the solve's churn (fitted at lag 5 too: cross-dataset 15.872 → 15.959 cm). As far as
  // the body travels: where the motion guard holds it as standing, the line carried the solve's
  // hops ahead (phone-AR input, standing gestures: 10 → 16 clips over the allowed pelvis speed;
  // 11 with the line so weighed).
  // The rotations keep the repeat: fitted too, the legs gained, the torso and arms lost, and the
  // joint jitter rose a quarter.
  bool pelvis_edge_fit = true;
  // Where the input is weak — a hand the tracker has lost (held by the other, one_hand_bridge.h),
  // both hands bridged across a dropout — and for `weak_input_hold_seconds` after (the returning
  // hand's cross-fade), the joint filter leans on the motion around the frame: its σ widens to
  // this, moving between the two over `weak_input_ramp_seconds` so the output does not step where
  // the filter changes (issue #25: re-entry jerk). ≤ joint_smoothing_sigma: never wider.
  float weak_input_joint_smoothing_sigma = 2.0f;
  double weak_input_hold_seconds = 0.5;
  double weak_input_ramp_seconds = 0.25;
  // Noisy input is weak too: where a tracked hand's input jitters by more than this (metres; the
  // σ of white noise told from the median size of its second differences over the last second,
  // which a hand's own motion at 30 Hz keeps below ~0.5 cm), the joint filter widens as above.
  // 0 = off.
  float noisy_input_metres = 0.025f;
  // A body that jitters is weak too (issues #22, #25): where the solved torso (head and shoulders,
  // before the filter) has jerked more than this many times as much as the input hands over the
  // last `weak_input_hold_seconds` (exponential means of third differences), the solve follows
  // the nearest frames' churn, not a motion, and the body's joint filter widens as above; the
  // hands' targets do not. In-lab input stays below it in 95% of frames (the development split's
  // 95th percentile, 8.5; median 4.3); input unlike the database (other people, labs, devices)
  // exceeds it in most. 0 = off.
  float jittery_body_ratio = 8.5f;
  // After the joint filter, two-bone arm IK puts each hand on the input wrist (as the legs are put
  // on their pins): the input smoothed by a centred Gaussian of this σ over the samples that have
  // arrived (zero phase where the lag allows, unlike A2's exponential smoothing); < 0 = off.
  float hand_target_sigma = 1.0f;
  // Before the arm IK, input beyond an arm's reach turns the torso towards it (reach_lean.h).
  ReachLeanOptions reach_lean;
  // Before the arm IK, an ankle below the database's planted ankle height is lifted to it by the
  // leg IK (the knee bends): a body whose solve sank with low input does not stand in the floor.
  bool feet_above_floor = true;

  // Last: the output pelvis moves no faster, and accelerates no harder, than the database's
  // bodies; frames whose input jumps are flagged (issue #22).
  MotionGuardOptions motion_guard;

  // Input dropouts up to this long are bridged (the input interpolated across them, frames
  // flagged kPredicted, one continuous body); longer ones end the segment. Hand trackers lose the
  // hands for up to a couple of seconds (out of the camera's view, a controller occluded); at
  // 0.25 s each such dropout restarted the body, and on device-like input with 0.1-2 s dropouts
  // the full method fell behind a plain lookup (docs/evaluation.md, issue #22).
  double max_gap_seconds = 2.0;

  // The tracked points are devices held in the hands, this many metres beyond the wrist joints
  // along the forearms (a phone in a closed grip, a controller's handle: ~0.08–0.10), their
  // orientation unknown (grip_offset.h). 0: the points are the wrists. At most kMaxGripOffset.
  float grip_offset = 0.0f;
};

inline constexpr float kMaxGripOffset = 0.3f;

// The A4 ankle path's filter σ (frames) a session of these options uses: a stream's its own.
inline float AnkleSmoothingSigma(const ReconstructionOptions& options) {
  return options.mode == StreamMode::kFixedLag ? options.ankle_path.stream_smoothing_sigma_frames
                                               : options.ankle_path.smoothing_sigma_frames;
}

}  // namespace mocap

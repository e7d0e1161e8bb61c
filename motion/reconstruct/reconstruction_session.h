// ReconstructionSession: docs/method.md A2–A7 as one pipeline that takes timestamped wrist samples one
// at a time and emits whole-body frames as soon as they are decided. Offline reconstruction is the
// same session fed a whole trajectory (ReconstructOffline), so the two cannot disagree.
//
//   samples → resample to the database rate (gaps, NaN refusal)
//           → A2 smoothing → A3 ankle cloud (K1)
//           → A4 DAG: sub-intervals of L frames, or fixed lag (frame t−D_a decided at t)
//           → A5 local pose model (K2) → A6 LM solve → A7 footskate cleanup
//           → A7 joint-space Gaussian (lag P) → frames out
// In fixed-lag mode the lag D is split: P = min(⌈3σ⌉, D) frames for the joint filter, the rest
// for the ankle path, so a frame leaves exactly D frames after its sample arrived.
//
// Thread safety: one session per stream; many sessions may share one ReconstructionDatabase.
#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "absl/status/statusor.h"
#include "motion/reconstruct/hand_rest.h"
#include "motion/reconstruct/landmark_confidence.h"
#include "motion/reconstruct/motion_guard.h"
#include "motion/reconstruct/one_hand_bridge.h"
#include "motion/reconstruct/reach_lean.h"
#include "motion/reconstruct/reconstruction_database.h"
#include "motion/reconstruct/reconstruction_options.h"
#include "motion/reconstruct/wrist_resampler.h"

namespace mocap {

class PoseMethod;

struct FrameDiagnostics {
  float wrist_neighbour_distance = 0;  // eq. 2 value of the nearest database frame
  int ankle_source_row = -1;           // database frame whose ankles the A4 path chose
  float pose_neighbour_distance = 0;   // eq. 8 (or eq. 2 for the wrists-only model) of the nearest
  float solver_cost = 0;               // A6 energy at the solution, the prior at its configured weight
  float prior_weight_factor = 1;       // the session's factor on that weight (unfamiliar_prior.h)
  int solver_evaluations = 0;
  std::array<float, 4> control_error{};  // metres: left/right wrist, left/right ankle before A7
  std::array<bool, 2> contact{};         // A7 planted flags (left, right)
  bool bridged = false;                  // input interpolated across a dropout
  // Per hand (left, right): seconds its input has not been real (GridSample::untracked_seconds).
  std::array<float, 2> untracked_seconds{};
  std::array<FadingGuess, 2> fading_guess{};  // per hand: a returning hand's guess share (GridSample)
  float session_log_cost = 0;                 // SessionCost's mean log A6 energy (landmark_confidence.h)
};

// What a frame's expected errors are told from (landmark_confidence.h).
inline ConfidenceCues ConfidenceCuesOf(const FrameDiagnostics& d) {
  return {.distance = d.pose_neighbour_distance,
          .wrist_fit = 0.5f * (d.control_error[0] + d.control_error[1]),
          .solver_cost = d.solver_cost,
          .session_log_cost = d.session_log_cost,
          .untracked_seconds = d.untracked_seconds,
          .fading_guess = d.fading_guess};
}

// What the engine makes of one hand's input in a frame (the states of issue #25). Both hands gone
// for longer than max_gap_seconds end the segment: no frame is made for that time.
enum class TrackingState {
  kTracked,      // the input moves as a hand can
  kImplausible,  // the input stepped faster than any hand in the database (a controller's jump,
                 // a tracker that repeated samples and caught up): the body does not follow it
  kPredicted,    // no input at this time: a dropout (up to max_gap_seconds) bridged by the input
                 // interpolated across it, or a hand the tracker lost held by the other one
                 // (one_hand_bridge.h) for up to max_gap_seconds
  kLost,         // the tracker has lost this hand for longer than max_gap_seconds while the other
                 // is tracked: the body goes on from the other hand, this one held by it
  kOutOfReach,   // the input is further from the body's shoulder than its arm reaches
                 // (kOutOfReachFactor × upper arm + forearm), or under the floor (hand_floor.h):
                 // the hand stops short of it
  kPutDown,      // the device lies still while the person moves (hand_rest.h): the body goes on
                 // from the other hand, this one carried with it as a lost one is
};

inline constexpr float kOutOfReachFactor = 1.1f;

struct ReconstructedFrame {
  int segment = 0;  // increments after each long input gap
  int index = 0;    // frame number in the session's output
  int frame_in_segment = 0;
  double time = 0.0;                                                    // seconds, on the input's clock
  Eigen::Quaternionf pelvis_rotation = Eigen::Quaternionf::Identity();  // world
  Eigen::Vector3f pelvis_position = Eigen::Vector3f::Zero();            // world, metres
  BodyPose pose;  // every joint's local rotation and the root translation
  // How far each body landmark is expected to be from the truth, metres (landmark_confidence.h).
  LandmarkErrors landmark_error{};
  std::array<Eigen::Vector3f, 2> ankles;  // A4 estimates (left, right), world metres
  // A2-smoothed input (with a grip offset, the devices' points taken back along the forearms the
  // body holds them with: where its wrists would be).
  std::array<Eigen::Vector3f, 2> wrists;
  FrameDiagnostics diagnostics;
  std::array<TrackingState, 2> hand_state{TrackingState::kTracked, TrackingState::kTracked};  // left, right
  // The motion guard (motion_guard.h) did not let the pelvis go where the solve put it: it moved
  // no faster than the database's bodies do instead.
  bool motion_limited = false;
  int put_down_hands() const {
    return (hand_state[0] == TrackingState::kPutDown) + (hand_state[1] == TrackingState::kPutDown);
  }
  bool implausible_input() const {
    return hand_state[0] == TrackingState::kImplausible || hand_state[1] == TrackingState::kImplausible;
  }
  // A7: where the footskate cleanup held each ankle (planted or releasing), re-imposed by leg IK
  // after the joint-space filter, which would otherwise let planted feet slide again. Where the
  // filter looks ahead (fixed lags of 1 or more, sub-intervals, whole clips) these are its eased
  // pins instead (EasePin).
  FootskateCleaner::AnkleTargets ankle_targets;
  // How firmly each ankle is held on its target: 1 on it; less, that fraction of the way there
  // from where the body puts it (the joint filter eases feet onto and off their pins).
  std::array<float, 2> ankle_target_weight = {1.0f, 1.0f};
};

struct SessionStatistics {
  long samples = 0, frames = 0, segments = 0, refused_samples = 0;
  // Hand-samples that repeated the hand's last position (a tracker that did not update), not
  // taken as input (wrist_resampler.h).
  long repeated_hand_samples = 0;
  // Wall time per stage, seconds (single thread): A2+A3, A4, A5+A6, A7.
  double cloud_seconds = 0, path_seconds = 0, pose_seconds = 0, post_seconds = 0;
};

class ReconstructionSession {
 public:
  // InvalidArgument for options out of range (K1, K2 < 1, negative window/lag, ...).
  static absl::StatusOr<std::unique_ptr<ReconstructionSession>> Create(
      std::shared_ptr<const ReconstructionDatabase> database, const ReconstructionOptions& options);
  ~ReconstructionSession();

  // One input sample; frames decided by it are appended to `out`. A refused sample (NaN, time
  // not increasing) returns InvalidArgument and leaves the session as it was.
  absl::Status Push(const WristSample& sample, std::vector<ReconstructedFrame>* out);
  // End of input: every remaining frame (with a slice deadline, those solved by then: call
  // Continue, or Finish again, until has_pending_frames() is false).
  absl::Status Finish(std::vector<ReconstructedFrame>* out);
  // Frames decided together (a sub-interval's window, a whole segment's: up to max_window_frames,
  // ~0.3 s of A5–A7 work) are solved only until `deadline` (at least one frame per call), so a
  // server can cut that work into bounded tasks (issue #24); the rest wait for Continue, and the
  // next Push or Finish solves them first. Default: no deadline.
  void SetSliceDeadline(std::chrono::steady_clock::time_point deadline) { slice_deadline_ = deadline; }
  // Ends every slice sooner, after the frame at which `yield()` is true (a server's other work
  // waits for the thread). Called once a frame.
  void SetSliceYield(bool (*yield)()) { slice_yield_ = yield; }
  // Decided frames not solved yet, or a finished segment whose last frames are still to come.
  bool has_pending_frames() const;
  // Pending frames (after Finish: the rest of the finish), until the slice deadline.
  absl::Status Continue(std::vector<ReconstructedFrame>* out);
  // Once `*cancel` is set (by another thread: the client went away, the deadline passed), Push
  // and Finish stop within one frame's work and return Cancelled; the session is then unusable.
  // The flag must outlive the session.
  void SetCancelFlag(const std::atomic<bool>* cancel) { cancel_ = cancel; }

  const ReconstructionDatabase& database() const { return *database_; }
  const ReconstructionOptions& options() const { return options_; }
  const SessionStatistics& statistics() const { return statistics_; }
  // Frames between a sample's arrival and its frame leaving (fixed lag: D; sub-interval: up to
  // L − 1 + the joint filter's lag; whole segment: unbounded, returns −1).
  int latency_frames() const;
  // Frames of per-frame state the open segment holds (its longest history): bounded by the
  // window, lag and kernel reaches, not by the session's length.
  int frames_held() const;

 private:
  struct Segment;
  ReconstructionSession(std::shared_ptr<const ReconstructionDatabase> database, const ReconstructionOptions& options);
  absl::Status CheckCancelled() const;
  absl::Status AcceptGridSample(const GridSample& sample, std::vector<ReconstructedFrame>* out);
  // A2 and onwards for the segment's next frame whose input has arrived.
  absl::Status ProcessFrame(std::vector<ReconstructedFrame>* out);
  // A declared grip offset: the segment's newest A2 device points become wrists (grip_offset.h).
  absl::Status DeviceToWrists(Segment& s) const;
  // Ends the open segment: its last frames decided, then solved (`sliced`: until the slice
  // deadline; the segment ends once all are).
  absl::Status EndSegment(bool sliced, std::vector<ReconstructedFrame>* out);
  // Sub-interval mode: the open window's best path (its DP has every frame) into the raw path.
  void DecideWindow(Segment& s);
  // Solves the decided frames in order (`sliced`: until slice_deadline_), then ends the segment
  // if it is ending.
  absl::Status SolvePending(bool sliced, std::vector<ReconstructedFrame>* out);
  // All a sliced call left (a finish included), whatever the deadline.
  absl::Status CompletePending(std::vector<ReconstructedFrame>* out);
  // Smooths the decided ankle path up to `up_to_frame` (the tentative continuation up to
  // `available` taken into the filter), plants its feet (PlantAnkleContacts) and solves those
  // frames; `segment_ends`: no frame follows.
  absl::Status DecideAnkles(int up_to_frame, int available, const std::vector<AnklePair>& tentative, bool segment_ends,
                            std::vector<ReconstructedFrame>* out);
  absl::Status SolveFrame(int frame, std::vector<ReconstructedFrame>* out);
  void EmitFiltered(bool flush, std::vector<ReconstructedFrame>* out);
  // A2's local linear fit of the input at `frame` over the samples that have arrived.
  SmoothedWrists FitInput(const Segment& s, int frame, const std::vector<float>& kernel) const;
  // Reads the newest input frame's noise (ReconstructionOptions::noisy_input_metres).
  void TrackInputNoise(Segment& s, const GridSample& sample) const;
  // Reads whether the solved body jitters (ReconstructionOptions::jittery_body_ratio) at `frame`,
  // solved and not yet filtered.
  void TrackBodyJitter(Segment& s, const ReconstructedFrame& frame) const;
  // Puts each foot with an A7 pin (`ankle_targets`) back on it by the leg IK, after the body moved:
  // all the way, or by `ankle_target_weight` of the way from where the body put it.
  // `world_rotations`, `world_positions`: scratch.
  void ReimposeAnklePins(ReconstructedFrame* frame, std::vector<Eigen::Quaternionf>* world_rotations,
                         std::vector<Eigen::Vector3f>* world_positions) const;
  // An ankle under the database's planted ankle height goes up to it by the leg IK.
  void KeepFeetAboveFloor(ReconstructedFrame* frame, std::vector<Eigen::Quaternionf>* world_rotations,
                          std::vector<Eigen::Vector3f>* world_positions) const;
  // Where a frame put the feet: its time and world ankles (left, right).
  struct EmittedFeet {
    double time;
    std::array<Eigen::Vector3f, 2> ankles;
  };
  // A foot moves no faster than the motion guard's foot bound (MotionGuard::foot_speed_bound) from
  // where the previous frame emitted it (`feet`; none at a segment's start): the leg IK holds it
  // back on its way. Sets `motion_limited` when it did.
  void LimitFootSpeed(const std::optional<EmittedFeet>& feet, ReconstructedFrame* frame,
                      std::vector<Eigen::Quaternionf>* world_rotations,
                      std::vector<Eigen::Vector3f>* world_positions) const;
  // Marks a tracked hand whose input lies beyond its arm's reach from the emitted body's shoulder,
  // or under the floor (`under_floor`, read from the smoothed input).
  void MarkOutOfReach(const std::array<Eigen::Vector3f, 2>& input, const std::array<bool, 2>& under_floor,
                      const std::vector<Eigen::Vector3f>& world_positions, ReconstructedFrame* frame) const;
  // Issue #25 item 2: a device put down (hand_rest.h) is no input of the body. Reads `sample`'s
  // devices and marks a put-down hand not tracked, so OneHandBridge carries it with the body from
  // the other hand, as a lost one (never both hands); returns the put-down hands.
  std::array<bool, 2> LetGoOfPutDownHands(WristSample* sample);
  // Drops per-frame state no stage will read again: memory bounded by window and lag.
  void ForgetSettledFrames();

  std::shared_ptr<const ReconstructionDatabase> database_;
  ReconstructionOptions options_;
  WristResampler resampler_;
  std::unique_ptr<Segment> segment_;
  SessionCost session_cost_;
  int next_segment_id_ = 0;
  int next_output_index_ = 0;
  int joint_filter_lag_ = 0;
  int ankle_lag_ = 0;
  int lookahead_ = 0;            // A2 frames (local linear smoothing)
  float grip_over_forearm_ = 0;  // options' grip_offset over the body's forearm (AddGripUncertainty)
  std::vector<float> ankle_kernel_, wrist_kernel_;
  // The joint filter's kernels from joint_smoothing_sigma (first) to
  // weak_input_joint_smoothing_sigma (last), 0.1 frame of σ apart; the hands' targets' alongside.
  std::vector<std::vector<float>> joint_kernels_, hand_kernels_;
  bool pelvis_edge_fit_ = false;  // the Gaussian joint filter fits the pelvis where its taps run out
  // Issue #22: the output pelvis moves as the database's bodies do, across segments too.
  MotionGuard motion_guard_;
  InputJumpDetector jump_detector_;
  std::array<HandRestDetector, 2> hand_rest_;  // left, right
  OneHandBridge one_hand_bridge_;
  ReachLean reach_lean_;
  std::unique_ptr<const PoseMethod> method_;  // the options' method: neighbours and pose (pose_method.h)
  SessionStatistics statistics_;
  const std::atomic<bool>* cancel_ = nullptr;
  std::chrono::steady_clock::time_point slice_deadline_ = std::chrono::steady_clock::time_point::max();
  bool (*slice_yield_)() = nullptr;
  bool finishing_ = false;  // Finish was called and has frames to come (has_pending_frames)
};

// The offline path: the same session fed every sample, then finished.
absl::StatusOr<std::vector<ReconstructedFrame>> ReconstructOffline(
    std::shared_ptr<const ReconstructionDatabase> database, const ReconstructionOptions& options,
    const std::vector<WristSample>& samples);

}  // namespace mocap

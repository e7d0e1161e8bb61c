#include "motion/reconstruct/reconstruction_session.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <deque>
#include <optional>

#include "motion/core/gaussian_kernel.h"
#include "motion/core/local_linear_weights.h"
#include "motion/core/low_pass_kernel.h"
#include "motion/core/rotation_vector.h"
#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"
#include "motion/reconstruct/ankle_cloud.h"
#include "motion/reconstruct/frame_history.h"
#include "motion/reconstruct/grip_offset.h"
#include "motion/reconstruct/hand_floor.h"
#include "motion/reconstruct/pose_method.h"
#include "motion/reconstruct/stream_ankle_planter.h"
#include "motion/reconstruct/unfamiliar_prior.h"

namespace mocap {
namespace {

// The midpoint of the two smoothed wrists (world metres): where the motion guard and the planted
// feet read the hands.
Eigen::Vector3f WristsMidpoint(const SmoothedWrists& w) { return 0.5f * (w.position[0] + w.position[1]); }

using Clock = std::chrono::steady_clock;

// How far the motion guard may move the body (metres) with its planted feet kept where they are.
constexpr float kPlantedFootReach = 0.05f;

double SecondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// Fixed-lag DP frame: a cloud, its path costs and best predecessors.
struct DpFrame {
  std::vector<AnkleCandidate> cloud;
  std::vector<float> cost;
  std::vector<int> from;
};

// Nodes of the cheapest path ending at the newest frame of `dp` (frames first.. of the segment),
// backtracked down to frame `from_frame`; element i is frame from_frame + i.
std::vector<int> BestPathFrom(const std::deque<DpFrame>& dp, int first, int from_frame) {
  const int last = first + static_cast<int>(dp.size()) - 1;
  std::vector<int> nodes(last - from_frame + 1);
  const std::vector<float>& last_cost = dp.back().cost;
  nodes.back() = static_cast<int>(std::min_element(last_cost.begin(), last_cost.end()) - last_cost.begin());
  for (int f = last; f > from_frame; --f) nodes[f - 1 - from_frame] = dp[f - first].from[nodes[f - from_frame]];
  return nodes;
}

}  // namespace

struct ReconstructionSession::Segment {
  Segment(int id, const ReconstructionDatabase& db, const ReconstructionOptions& o)
      : id(id),
        smoother(o.smoothing, db.frame_time()),
        grip(o.grip_offset),
        window_dp(db.frame_time(), o.ankle_path),
        cleaner(db.body(), db.planted_ankle_height(), db.frame_time(), o.footskate, o.mode == StreamMode::kFixedLag),
        planter(db.planted_ankle_height(), db.frame_time(), o.footskate, o.motion_guard.standing_hands_speed) {}
  int id;
  WristSmoother smoother;
  float cloud_heading = 0.0f, pose_heading = 0.0f;
  GripOffset grip;  // the device points' way back to the wrists
  // Per frame of the segment; frames no stage reads again are forgotten (ForgetSettledFrames).
  FrameHistory<SmoothedWrists> wrists;
  FrameHistory<std::array<Eigen::Vector3f, 2>> input;  // resampled, unsmoothed wrists
  FrameHistory<double> times;
  FrameHistory<std::array<float, 2>> untracked;     // GridSample::untracked_seconds
  FrameHistory<std::array<FadingGuess, 2>> fading;  // GridSample::fading_guess
  FrameHistory<std::array<bool, 2>> put_down;       // GridSample::put_down
  FrameHistory<char> bridged;
  FrameHistory<float> wrist_distance;
  // A4 state.
  FrameHistory<AnklePair> raw;  // decided (unsmoothed) path
  FrameHistory<int> raw_rows;
  std::vector<std::vector<AnkleCandidate>> window;  // sub-interval mode: the open window's clouds
  AnkleWindowDp window_dp;                          // and its DP, a frame at a time
  std::optional<AnkleCandidate> start;
  std::deque<DpFrame> dp;  // fixed-lag mode: frames dp_first.. of the running DP
  int dp_first = 0;
  FrameHistory<AnklePair> ankles;            // decided and smoothed ankle controls
  std::vector<AnklePair> ankle_batch;        // DecideAnkles's frames, before they join `ankles`
  std::vector<Eigen::Vector2f> hands_batch;  // their input wrists' midpoints over the ground
  // Frames [solved, decided) have their controls and wait for A5–A7 (SolvePending); `ending`:
  // once they are solved the segment ends (EndSegment).
  int solved = 0, decided = 0;
  bool ending = false;
  // Every per-frame history above, so that what holds for all of them is said once (a new
  // history is one line here, and ForgetSettledFrames forgets it too).
  template <typename F>
  void ForEachHistory(F&& f) {
    f(wrists), f(input), f(times), f(untracked), f(fading), f(put_down), f(bridged), f(wrist_distance);
    f(raw), f(raw_rows), f(ankles);
  }
  // A5–A7 state.
  std::optional<SolvedPose> previous, before_previous;
  FootskateCleaner cleaner;
  StreamAnklePlanter planter;           // fixed lag: the decided ankles planted as they come
  std::deque<ReconstructedFrame> post;  // solved frames waiting for the joint filter
  int post_first = 0;
  int emitted = 0;
  // The joint filter's width (an index of joint_kernels_, moving by fractions) and when the input
  // was last weak (ReconstructionOptions::weak_input_joint_smoothing_sigma).
  float joint_filter_level = 0.0f;
  float hand_filter_level = 0.0f;  // the hands' targets widen with weak input only
  double weak_input_time = -1e30;
  // The body's jitter (ReconstructionOptions::jittery_body_ratio): the solved torso's and the
  // input hands' last four positions (oldest first), the exponential means of their third
  // differences' sizes, and the time the torso last jerked beyond the ratio.
  std::array<std::array<Eigen::Vector3f, 4>, 2> torso_and_hands{};
  int jitter_frames = 0;
  float torso_jerk = 0.0f, hands_jerk = 0.0f;
  double jittery_time = -1e30;
  std::vector<Eigen::Quaternionf> jitter_rotations;  // forward kinematics' scratch
  std::vector<Eigen::Vector3f> jitter_positions;
  // Input noise (ReconstructionOptions::noisy_input_metres): each tracked hand's second
  // differences over the last second, and the input time it last read as noisy.
  std::array<std::deque<float>, 2> second_differences;
  double noisy_input_time = -1e30;
  Eigen::Vector3f reach_shift = Eigen::Vector3f::Zero();  // reach_lean.h: where the body stepped to
  Eigen::Vector3f reach_turn = Eigen::Vector3f::Zero();   // reach_lean.h: the torso's turn
  std::optional<EmittedFeet> emitted_feet;                // the last emitted frame's (LimitFootSpeed)
};

ReconstructionSession::ReconstructionSession(std::shared_ptr<const ReconstructionDatabase> database,
                                             const ReconstructionOptions& options)
    : database_(std::move(database)),
      options_(options),
      resampler_(database_->frame_time(), options.max_gap_seconds),
      session_cost_(database_->frame_time()),
      motion_guard_(database_->motion_limits(), database_->frame_time(), options.motion_guard),
      jump_detector_(database_->motion_limits(), database_->frame_time(), options.motion_guard),
      hand_rest_{HandRestDetector(WristSpan(database_->body())), HandRestDetector(WristSpan(database_->body()))},
      reach_lean_(database_->body().skeleton(), database_->rig().topology.landmarks, options.reach_lean),
      method_(MakePoseMethod(options)) {
  options_.ankle_path.planted_ankle_height = database_->planted_ankle_height();
  if (const float forearm = ForearmLength(database_->body()); forearm > 0.0f) {
    grip_over_forearm_ = options_.grip_offset / forearm;
  }
  ankle_kernel_ = GaussianKernel(AnkleSmoothingSigma(options_));
  // The sharp filter's lag (8σ) costs nothing only where the output waits for the whole input.
  const bool low_pass = options_.joint_low_pass && options_.mode == StreamMode::kSubInterval && options_.window == 0;
  auto joint_kernel = [low_pass](float sigma) { return low_pass ? LowPassKernel(sigma) : GaussianKernel(sigma); };
  joint_kernels_ = {joint_kernel(options_.joint_smoothing_sigma)};
  pelvis_edge_fit_ = options_.pelvis_edge_fit && !low_pass;  // the sharp low-pass's weights go negative
  if (options_.joint_smoothing_sigma > 0) {
    const float widest = options_.weak_input_joint_smoothing_sigma;
    const int steps = static_cast<int>(std::ceil((widest - options_.joint_smoothing_sigma) / 0.1f - 1e-3f));
    for (int i = 1; i <= steps; ++i)
      joint_kernels_.push_back(joint_kernel(std::min(widest, options_.joint_smoothing_sigma + 0.1f * i)));
  }
  // The hands' targets widen with it (by as many frames of σ): a body smoothed more than the hands
  // it reaches for bends its elbows to make up the difference.
  for (size_t i = 0; i < joint_kernels_.size(); ++i)
    hand_kernels_.push_back(GaussianKernel(std::max(0.0f, options_.hand_target_sigma) + 0.1f * static_cast<float>(i)));
  const bool local_linear = options_.smoothing.local_linear_sigma > 0.0f;
  if (local_linear) wrist_kernel_ = GaussianKernel(options_.smoothing.local_linear_sigma);
  const int radius = static_cast<int>(joint_kernels_.front().size()) / 2;  // the lag is the usual filter's
  const int reach = static_cast<int>(wrist_kernel_.size()) / 2;
  const int lookahead = local_linear ? std::clamp(options_.smoothing.lookahead, 0, reach) : 0;
  if (options_.mode == StreamMode::kFixedLag) {
    // The lag D is shared: A2's look-ahead first, then the joint filter up to 2σ ahead (the
    // Gaussian's weight beyond is 2%, clamped to the newest solved frame), the rest for the ankle
    // path, whose decision gains most from a frame or two of look-ahead: at D = 5, 3 frames for
    // the filter and none for the path measured 2.43 cm on the standard split, 2 and 1 2.25
    // (docs/method.md A4). A2 takes its frames beyond the first only where the path keeps two
    // (stop 67: at D = 5, A2 1 + filter 2 + path 2 against 2 + 2 + 1: standard split 2.110 →
    // 2.086 cm, cross-dataset clips over the allowed speed 5 → 1).
    const int filter_ahead = std::min(radius, static_cast<int>(std::ceil(2.0f * options_.joint_smoothing_sigma)));
    constexpr int kPathLookahead = 2;
    lookahead_ = std::min({lookahead, options_.lag, std::max(1, options_.lag - filter_ahead - kPathLookahead)});
    joint_filter_lag_ = std::min(filter_ahead, options_.lag - lookahead_);
    ankle_lag_ = options_.lag - lookahead_ - joint_filter_lag_;
  } else {
    lookahead_ = lookahead;
    joint_filter_lag_ = radius;
  }
}

ReconstructionSession::~ReconstructionSession() = default;

absl::StatusOr<std::unique_ptr<ReconstructionSession>> ReconstructionSession::Create(
    std::shared_ptr<const ReconstructionDatabase> database, const ReconstructionOptions& options) {
  if (!database) return absl::InvalidArgumentError("no reconstruction database");
  if (options.ankle_candidates < 1 || options.ankle_candidates > 100000) {
    return absl::InvalidArgumentError(
        StrCat("K1 (ankle candidates) must be in [1, 100000], not ", options.ankle_candidates));
  }
  if (options.pose_neighbours < 2 || options.pose_neighbours > 100000) {
    return absl::InvalidArgumentError(
        StrCat("K2 (pose neighbours) must be in [2, 100000], not ", options.pose_neighbours));
  }
  if (options.pose_components < 1 || options.pose_components > 64) {
    return absl::InvalidArgumentError(
        StrCat("pose model components must be in [1, 64], not ", options.pose_components));
  }
  if (options.window < 0 || options.lag < 0 || options.lag > 600) {
    return absl::InvalidArgumentError("window and lag must be ≥ 0 (lag ≤ 600 frames)");
  }
  if (!(options.max_gap_seconds > 0) || !(options.joint_smoothing_sigma >= 0) || options.joint_smoothing_sigma > 30 ||
      !(options.ankle_path.smoothing_sigma_frames >= 0) || options.ankle_path.smoothing_sigma_frames > 30 ||
      !(options.ankle_path.stream_smoothing_sigma_frames >= 0) ||
      options.ankle_path.stream_smoothing_sigma_frames > 30 || !(options.weak_input_joint_smoothing_sigma <= 30) ||
      !(options.weak_input_hold_seconds >= 0) || !(options.weak_input_ramp_seconds >= 0) ||
      !std::isfinite(options.weak_input_hold_seconds) || !(options.noisy_input_metres >= 0) ||
      !(options.jittery_body_ratio >= 0) || !std::isfinite(options.jittery_body_ratio)) {
    return absl::InvalidArgumentError("gap and smoothing parameters out of range");
  }
  if (!(options.grip_offset >= 0.0f && options.grip_offset <= kMaxGripOffset)) {
    return absl::InvalidArgumentError(StrCat("grip offset must be in [0, ", kMaxGripOffset,
                                             "] m (a device held in the hand), not ", options.grip_offset));
  }
  return std::unique_ptr<ReconstructionSession>(new ReconstructionSession(std::move(database), options));
}

int ReconstructionSession::latency_frames() const {
  if (!method_->uses_ankles()) return lookahead_ + joint_filter_lag_;
  if (options_.mode == StreamMode::kFixedLag) return options_.lag;
  const int window = options_.window > 0 ? options_.window : options_.max_window_frames;
  return window > 0 ? lookahead_ + window - 1 + joint_filter_lag_ : -1;
}

int ReconstructionSession::frames_held() const {
  if (!segment_) return 0;
  const Segment& s = *segment_;
  auto held = [](const auto& history) { return history.stored(); };
  return std::max({held(s.input), held(s.wrists), held(s.times), held(s.untracked), held(s.fading), held(s.put_down),
                   held(s.bridged), held(s.wrist_distance), held(s.raw), held(s.raw_rows), held(s.ankles),
                   static_cast<int>(s.window.size()), static_cast<int>(s.dp.size()), static_cast<int>(s.post.size())});
}

absl::Status ReconstructionSession::Push(const WristSample& sample, std::vector<ReconstructedFrame>* out) {
  // Checked before the bridge sees it (one_hand_bridge.h holds a lost hand by the other), so a
  // refused sample leaves the session as it was without copying the bridge's state per sample.
  if (absl::Status status = resampler_.Check(sample); !status.ok()) {
    ++statistics_.refused_samples;
    return status;
  }
  WristSample filled = sample;
  const std::array<bool, 2> put_down = LetGoOfPutDownHands(&filled);
  std::array<float, 2> untracked{};
  std::array<FadingGuess, 2> fading{};
  if (!one_hand_bridge_.Fill(&filled, &untracked, &fading)) return absl::OkStatus();  // no hand to go on from yet
  std::vector<GridSample> grid;
  MOCAP_RETURN_IF_ERROR(resampler_.Push(filled, &grid, untracked, fading, put_down));
  ++statistics_.samples;
  statistics_.repeated_hand_samples = resampler_.repeated_hand_samples();
  for (const GridSample& g : grid) MOCAP_RETURN_IF_ERROR(AcceptGridSample(g, out));
  return absl::OkStatus();
}

std::array<bool, 2> ReconstructionSession::LetGoOfPutDownHands(WristSample* sample) {
  const std::array<Eigen::Vector3f, 2> hands = {sample->left, sample->right};
  // The detector reads only the devices themselves: a hand the tracker lost says nothing.
  const bool observed = sample->tracked[0] && sample->tracked[1];
  std::array<bool, 2> put_down{};
  for (int side = 0; side < 2; ++side) {
    const bool before = hand_rest_[side].put_down();
    put_down[side] =
        observed ? hand_rest_[side].Update(sample->time, hands[side], hands[1 - side]) : hand_rest_[side].Unobserved();
    // It lay still a while before it could be told, while its person walked on.
    if (put_down[side] && !before) one_hand_bridge_.Carry(side, hand_rest_[side].other_travel_since_set_down());
  }
  for (int side = 0; side < 2; ++side) {  // never both: the body needs a hand to go on from
    if (put_down[side] && !put_down[1 - side] && sample->tracked[1 - side]) sample->tracked[side] = false;
  }
  return put_down;
}

absl::Status ReconstructionSession::Finish(std::vector<ReconstructedFrame>* out) {
  if (!finishing_) {
    std::vector<GridSample> waiting;  // frames that waited for a repeating hand's next position
    resampler_.Flush(&waiting);
    for (const GridSample& g : waiting) MOCAP_RETURN_IF_ERROR(AcceptGridSample(g, out));
    finishing_ = true;
    resampler_.Reset();
    one_hand_bridge_.Reset();
  }
  MOCAP_RETURN_IF_ERROR(EndSegment(true, out));
  if (!segment_) finishing_ = false;
  return absl::OkStatus();
}

absl::Status ReconstructionSession::Continue(std::vector<ReconstructedFrame>* out) {
  return finishing_ ? Finish(out) : SolvePending(true, out);
}

absl::Status ReconstructionSession::CompletePending(std::vector<ReconstructedFrame>* out) {
  if (!finishing_) return SolvePending(false, out);
  MOCAP_RETURN_IF_ERROR(EndSegment(false, out));
  finishing_ = false;
  return absl::OkStatus();
}

absl::Status ReconstructionSession::CheckCancelled() const {
  if (cancel_ != nullptr && cancel_->load(std::memory_order_relaxed))
    return absl::CancelledError("reconstruction cancelled");
  return absl::OkStatus();
}

void ReconstructionSession::TrackInputNoise(Segment& s, const GridSample& sample) const {
  if (options_.noisy_input_metres <= 0) return;
  const int newest = s.input.size() - 1;
  const size_t window = static_cast<size_t>(std::lround(1.0 / database_->frame_time()));  // one second
  float noise = 0.0f;
  for (int side = 0; side < 2; ++side) {
    std::deque<float>& history = s.second_differences[side];
    // A guessed or bridged hand says nothing of the device's noise.
    if (newest - 2 < s.input.first() || sample.untracked_seconds[side] > 0 || sample.fading_guess[side].weight > 0 ||
        sample.bridged) {
      history.clear();
      continue;
    }
    history.push_back((s.input[newest][side] - 2.0f * s.input[newest - 1][side] + s.input[newest - 2][side]).norm());
    if (history.size() > window) history.pop_front();
    if (history.size() < window) continue;
    std::array<float, 256> sorted;  // one second at up to 256 frames per second
    const size_t n = std::min(history.size(), sorted.size());
    std::copy_n(history.end() - static_cast<std::ptrdiff_t>(n), n, sorted.begin());
    std::nth_element(sorted.begin(), sorted.begin() + n / 2, sorted.begin() + n);
    // White noise of σ per axis: a second difference's size has median ≈ 1.54·√6·σ (χ with 3
    // degrees of freedom); the hand's own motion adds little at 30 Hz.
    noise = std::max(noise, sorted[n / 2] / (1.54f * std::sqrt(6.0f)));
  }
  if (noise > options_.noisy_input_metres) s.noisy_input_time = sample.time;
}

void ReconstructionSession::TrackBodyJitter(Segment& s, const ReconstructedFrame& frame) const {
  if (options_.jittery_body_ratio <= 0) return;
  const BodyLandmarks& l = database_->rig().topology.landmarks;
  database_->body().WorldTransforms(frame.pose, &s.jitter_rotations, &s.jitter_positions);
  const std::array<Eigen::Vector3f, 2> newest = {
      (s.jitter_positions[l.head] + s.jitter_positions[l.left_shoulder] + s.jitter_positions[l.right_shoulder]) / 3.0f,
      0.5f * (frame.wrists[0] + frame.wrists[1])};
  const double dt = database_->frame_time();
  const float rate = static_cast<float>(dt / std::max(dt, options_.weak_input_hold_seconds));
  float jerk[2];
  for (int k = 0; k < 2; ++k) {
    std::array<Eigen::Vector3f, 4>& p = s.torso_and_hands[k];
    std::rotate(p.begin(), p.begin() + 1, p.end());
    p[3] = newest[k];
    jerk[k] = (p[3] - 3.0f * p[2] + 3.0f * p[1] - p[0]).norm();
  }
  if (++s.jitter_frames < 4) return;  // a third difference needs four frames
  s.torso_jerk += rate * (jerk[0] - s.torso_jerk);
  s.hands_jerk += rate * (jerk[1] - s.hands_jerk);
  // Read once the means span their time constant: a segment's first frames say little.
  if ((s.jitter_frames - 3) * dt > options_.weak_input_hold_seconds &&
      s.torso_jerk > options_.jittery_body_ratio * s.hands_jerk)
    s.jittery_time = frame.time;
}

absl::Status ReconstructionSession::AcceptGridSample(const GridSample& sample, std::vector<ReconstructedFrame>* out) {
  MOCAP_RETURN_IF_ERROR(CheckCancelled());
  MOCAP_RETURN_IF_ERROR(CompletePending(out));  // what a sliced call left, before anything newer
  if (sample.starts_segment) MOCAP_RETURN_IF_ERROR(EndSegment(false, out));
  if (!segment_) {
    segment_ = std::make_unique<Segment>(next_segment_id_++, *database_, options_);
    ++statistics_.segments;
  }
  Segment& s = *segment_;
  s.input.push_back({sample.left, sample.right});
  s.times.push_back(sample.time);
  s.untracked.push_back(sample.untracked_seconds);
  s.fading.push_back(sample.fading_guess);
  s.put_down.push_back(sample.put_down);
  TrackInputNoise(s, sample);
  s.bridged.push_back(sample.bridged);
  // A2 looks `lookahead_` frames ahead: frame t is processed once t + lookahead_ has arrived.
  while (static_cast<int>(s.wrists.size()) + lookahead_ < static_cast<int>(s.input.size())) {
    MOCAP_RETURN_IF_ERROR(ProcessFrame(out));
  }
  return absl::OkStatus();
}

absl::Status ReconstructionSession::DeviceToWrists(Segment& s) const {
  SmoothedWrists& points = s.wrists.back();
  if (!s.grip.knows_forearms() || !method_->uses_ankles()) {
    // No earlier query to read the forearms from (or no cloud to come): the device points' own
    // nearest frame's.
    std::vector<AnkleCandidate> nearest;
    float heading = s.cloud_heading;
    MOCAP_RETURN_IF_ERROR(FindAnkleCloud(database_->wrist_index(), database_->frames(),
                                         database_->wrist_feature_options(), points, 1, &heading, &nearest));
    s.grip.Remember(*database_, nearest);
  }
  s.grip.ToWrists(s.cloud_heading, &points);
  return absl::OkStatus();
}

absl::Status ReconstructionSession::ProcessFrame(std::vector<ReconstructedFrame>* out) {
  MOCAP_RETURN_IF_ERROR(CheckCancelled());
  MOCAP_RETURN_IF_ERROR(SolvePending(false, out));
  Segment& s = *segment_;
  const int t = static_cast<int>(s.wrists.size());
  auto start = Clock::now();
  if (options_.smoothing.local_linear_sigma > 0.0f) {
    s.wrists.push_back(FitInput(s, t, wrist_kernel_));
  } else {
    s.wrists.push_back(s.smoother.Push(s.input[t][0], s.input[t][1]));
  }
  if (s.grip.active()) MOCAP_RETURN_IF_ERROR(DeviceToWrists(s));
  if (!method_->uses_ankles()) {
    s.wrist_distance.push_back(0.0f);
    statistics_.cloud_seconds += SecondsSince(start);
    s.decided = t + 1;
    return SolvePending(true, out);
  }
  std::vector<AnkleCandidate> cloud;
  MOCAP_RETURN_IF_ERROR(FindAnkleCloud(database_->wrist_index(), database_->frames(),
                                       database_->wrist_feature_options(), s.wrists.back(), options_.ankle_candidates,
                                       &s.cloud_heading, &cloud));
  s.wrist_distance.push_back(cloud.front().wrist_distance);
  if (s.grip.active()) s.grip.Remember(*database_, cloud);
  statistics_.cloud_seconds += SecondsSince(start);
  start = Clock::now();
  if (options_.mode == StreamMode::kSubInterval) {
    if (s.window.empty()) {
      s.window_dp.Start(s.start, cloud);
    } else {
      s.window_dp.Step(s.window.back(), cloud);
    }
    s.window.push_back(std::move(cloud));
    const int window = options_.window > 0 ? options_.window : options_.max_window_frames;
    if (window > 0 && static_cast<int>(s.window.size()) == window) {
      DecideWindow(s);
      statistics_.path_seconds += SecondsSince(start);
      return DecideAnkles(static_cast<int>(s.raw.size()), static_cast<int>(s.raw.size()), {}, false, out);
    }
    statistics_.path_seconds += SecondsSince(start);
    return absl::OkStatus();
  }
  // Fixed lag: extend the running DP by one frame, then decide frame t − D_a on today's best path.
  const float dt = static_cast<float>(database_->frame_time());
  DpFrame frame;
  if (s.dp.empty()) {
    frame.cost.assign(cloud.size(), 0.0f);
    frame.from.assign(cloud.size(), -1);
    AddAnkleDataCost(cloud, options_.ankle_path, &frame.cost);
  } else {
    AnkleDagStep(s.dp.back().cloud, s.dp.back().cost, cloud, dt, options_.ankle_path, &frame.cost, &frame.from);
    AddAnkleDataCost(cloud, options_.ankle_path, &frame.cost);
    const float lowest = *std::min_element(frame.cost.begin(), frame.cost.end());
    for (float& c : frame.cost) c -= lowest;  // path costs only compare within a frame: keep them small
  }
  frame.cloud = std::move(cloud);
  s.dp.push_back(std::move(frame));
  const int decide = t - ankle_lag_;
  if (decide < 0) {
    statistics_.path_seconds += SecondsSince(start);
    return absl::OkStatus();
  }
  const std::vector<int> nodes = BestPathFrom(s.dp, s.dp_first, decide);
  const AnkleCandidate& chosen = s.dp[decide - s.dp_first].cloud[nodes[0]];
  s.raw.push_back(AnklesOf(chosen));
  s.raw_rows.push_back(chosen.row);
  std::vector<AnklePair> tentative;
  for (int f = decide + 1; f <= t; ++f) tentative.push_back(AnklesOf(s.dp[f - s.dp_first].cloud[nodes[f - decide]]));
  while (s.dp_first < decide) {  // later backtracks stop at decide + 1
    s.dp.pop_front();
    ++s.dp_first;
  }
  statistics_.path_seconds += SecondsSince(start);
  return DecideAnkles(decide + 1, s.raw.size() + static_cast<int>(tentative.size()), tentative, false, out);
}

absl::Status ReconstructionSession::DecideAnkles(int up_to_frame, int available,
                                                 const std::vector<AnklePair>& tentative, bool segment_ends,
                                                 std::vector<ReconstructedFrame>* out) {
  Segment& s = *segment_;
  const int radius = static_cast<int>(ankle_kernel_.size()) / 2;
  const int first = s.ankles.size();
  if (first >= up_to_frame) return absl::OkStatus();
  // The decided path, then the tentative continuation, from the filter's reach onwards.
  const int low = std::max(0, first - radius);
  const std::span<const AnklePair> decided = s.raw.Since(low);
  std::vector<AnklePair> path(decided.begin(), decided.end());
  path.insert(path.end(), tentative.begin(), tentative.end());
  const int count = available - low;
  std::vector<AnklePair>& batch = s.ankle_batch;  // frames first.. up_to_frame
  batch.clear();
  const float edge_fit_step = options_.ankle_path.edge_fit_speed * static_cast<float>(database_->frame_time());
  for (int f = first; f < up_to_frame; ++f) {
    batch.push_back(SmoothAnkleAt(path, ankle_kernel_, f - low, count, edge_fit_step));
  }
  // Offline, or a window's worth at a time: planted feet at their contacts' means (A7).
  const AnklePair* before = first > 0 ? &s.ankles[first - 1] : nullptr;
  std::vector<Eigen::Vector2f>& hands = s.hands_batch;
  hands.clear();
  for (int f = first; f < up_to_frame; ++f) {
    const Eigen::Vector3f midpoint = WristsMidpoint(s.wrists[f]);
    hands.emplace_back(midpoint.x(), midpoint.z());
  }
  PlantAnkleContacts(batch, before, segment_ends, database_->planted_ankle_height(), database_->frame_time(),
                     options_.footskate, {hands, options_.motion_guard.standing_hands_speed});
  if (options_.mode == StreamMode::kFixedLag && options_.footskate.stream_plant_ankles) {
    for (size_t i = 0; i < batch.size(); ++i) {
      const SmoothedWrists& wrists = s.wrists[first + static_cast<int>(i)];
      s.planter.Next(&batch[i], {Eigen::Vector2f(wrists.position[0].x(), wrists.position[0].z()),
                                 Eigen::Vector2f(wrists.position[1].x(), wrists.position[1].z())});
    }
  }
  s.ankles.append(batch.begin(), batch.end());
  s.decided = up_to_frame;
  return SolvePending(true, out);
}

void ReconstructionSession::DecideWindow(Segment& s) {
  const AnkleWindowResult solved = s.window_dp.Best(s.window);
  s.start = s.window.back()[solved.nodes.back()];
  for (size_t i = 0; i < s.window.size(); ++i) s.raw_rows.push_back(s.window[i][solved.nodes[i]].row);
  s.raw.append(solved.ankles.begin(), solved.ankles.end());
  s.window.clear();
}

absl::Status ReconstructionSession::SolvePending(bool sliced, std::vector<ReconstructedFrame>* out) {
  if (!segment_) return absl::OkStatus();
  Segment& s = *segment_;
  while (s.solved < s.decided) {
    MOCAP_RETURN_IF_ERROR(SolveFrame(s.solved, out));
    ++s.solved;
    if (sliced && (Clock::now() >= slice_deadline_ || (slice_yield_ != nullptr && slice_yield_()))) break;
  }
  if (s.solved < s.decided || !s.ending) return absl::OkStatus();
  EmitFiltered(true, out);
  segment_.reset();
  return absl::OkStatus();
}

bool ReconstructionSession::has_pending_frames() const {
  return segment_ && (segment_->solved < segment_->decided || segment_->ending || finishing_);
}

absl::Status ReconstructionSession::SolveFrame(int f, std::vector<ReconstructedFrame>* out) {
  MOCAP_RETURN_IF_ERROR(CheckCancelled());
  Segment& s = *segment_;
  const auto start = Clock::now();
  const ReconstructionDatabase& db = *database_;
  const SmoothedWrists& wrists = s.wrists[f];
  const bool full = method_->uses_ankles();
  const ReferenceFrame ref =
      WristReferenceFrame(wrists.position[0], wrists.position[1], s.pose_heading, &s.pose_heading);
  FrameFeatures query = WristQueryFeatures(ref, wrists);
  AnklePair ankles = {Eigen::Vector3f::Zero(), Eigen::Vector3f::Zero()};  // zero where the method estimates none
  // The ankles' velocities are those of the database frame A4 chose, in its wrist frame as the
  // eq. 8 index holds them (docs/method.md A5), not the path's frame-to-frame difference: where
  // the path changes its mind (a stream's decision each frame, a stream's first frames) that
  // difference is metres a second no ankle moved, and the query lands far from every frame.
  const DatabaseFrame* chosen = full ? &db.frames()[s.raw_rows[f]] : nullptr;
  for (int side = 0; side < 2 && full; ++side) {
    ankles[side] = s.ankles[f][side];
    const Eigen::Vector3f ap = ref.ToLocal(ankles[side]);
    for (int axis = 0; axis < 3; ++axis) {
      query.ankle_position[side][axis] = ap[axis];
      query.ankle_velocity[side][axis] = chosen->ankle_velocity[side][axis];
    }
  }
  MOCAP_ASSIGN_OR_RETURN(const std::vector<Neighbour> neighbours, method_->Neighbours(db, query));
  if (!full) s.wrist_distance[f] = neighbours.front().distance;
  const int nearest = neighbours.front().row;
  const ControlTargets targets = {wrists.position[0], wrists.position[1], ankles[0], ankles[1]};
  const float prior_factor =
      UnfamiliarPriorFactor(options_.unfamiliar_prior, session_cost_.mean(), session_cost_.frames());
  MOCAP_ASSIGN_OR_RETURN(SolvedPose solved,
                         method_->Pose(db, neighbours, ref, targets,
                                       {.previous = s.previous ? &*s.previous : nullptr,
                                        .before_previous = s.before_previous ? &*s.before_previous : nullptr,
                                        .prior_weight_factor = prior_factor}));
  if (method_->solves()) {
    s.before_previous = std::move(s.previous);
    s.previous = solved;
  }
  statistics_.pose_seconds += SecondsSince(start);
  const auto post_start = Clock::now();
  ReconstructedFrame frame;
  frame.segment = s.id;
  frame.frame_in_segment = f;
  frame.time = s.times[f];
  frame.pose = db.body().Pose(solved.pelvis_rotation, solved.pelvis_position, solved.pose_feature.data() + 2);
  frame.pelvis_position = solved.pelvis_position;  // the joint filter averages it (EmitFiltered)
  frame.pelvis_rotation = solved.pelvis_rotation;
  if (!full) {
    // Baselines estimate no ankles: report where their pose puts them.
    std::vector<Eigen::Quaternionf> rotations;
    std::vector<Eigen::Vector3f> positions;
    db.body().WorldTransforms(frame.pose, &rotations, &positions);
    ankles = {positions[db.rig().topology.landmarks.left_ankle], positions[db.rig().topology.landmarks.right_ankle]};
  }
  frame.ankles = ankles;
  frame.wrists = {wrists.position[0], wrists.position[1]};
  FrameDiagnostics& d = frame.diagnostics;
  d.wrist_neighbour_distance = s.wrist_distance[f];
  d.ankle_source_row = full ? s.raw_rows[f] : nearest;
  d.pose_neighbour_distance = neighbours.front().distance;
  d.solver_cost = CostAtConfiguredPrior(solved, options_.solver.prior_weight, prior_factor);
  d.prior_weight_factor = prior_factor;
  d.solver_evaluations = solved.evaluations;
  for (int c = 0; c < kNumControlPoints; ++c) d.control_error[c] = solved.control_error[c];
  d.untracked_seconds = s.untracked[f];
  d.fading_guess = s.fading[f];
  d.bridged = s.bridged[f];
  TrackBodyJitter(s, frame);
  d.session_log_cost = session_cost_.Add(d.solver_cost);
  frame.landmark_error = ExpectedLandmarkErrors(ConfidenceCuesOf(d));
  AddGripUncertainty(grip_over_forearm_, &frame.landmark_error);
  if (full) d.contact = s.cleaner.Process(ankles, &db.frames()[s.raw_rows[f]], &frame.pose, &frame.ankle_targets);
  s.post.push_back(std::move(frame));
  EmitFiltered(false, out);
  statistics_.post_seconds += SecondsSince(post_start);
  return absl::OkStatus();
}

void ReconstructionSession::EmitFiltered(bool flush, std::vector<ReconstructedFrame>* out) {
  Segment& s = *segment_;
  const int widest_radius = static_cast<int>(joint_kernels_.back().size()) / 2;
  const int last = s.post_first + static_cast<int>(s.post.size()) - 1;  // newest solved frame
  const float levels = static_cast<float>(joint_kernels_.size() - 1);
  const float level_step =
      levels * static_cast<float>(database_->frame_time() / std::max(1e-3, options_.weak_input_ramp_seconds));
  const BodyModel& body = database_->body();
  const BodyLandmarks& l = database_->rig().topology.landmarks;
  const int wrist_joints[2] = {l.left_wrist, l.right_wrist};
  std::vector<Eigen::Quaternionf> world_rotations;
  std::vector<Eigen::Vector3f> world_positions;
  std::vector<std::optional<Eigen::Vector3f>> pins;  // a foot's, over the joint filter's reach
  std::vector<float> pelvis_weights;                 // the line's, where the filter's taps run out
  while (s.emitted <= last && (flush || s.emitted + joint_filter_lag_ <= last)) {
    const int e = s.emitted;
    ReconstructedFrame frame = s.post[e - s.post_first];
    const std::array<float, 2>& untracked = frame.diagnostics.untracked_seconds;
    if (frame.diagnostics.bridged || untracked[0] > 0 || untracked[1] > 0) s.weak_input_time = frame.time;
    s.weak_input_time = std::max(s.weak_input_time, s.noisy_input_time);
    if (e == 0 && s.id > 0) {  // the body comes back after a dropout too long to bridge: no motion before it
      s.weak_input_time = frame.time;
      s.joint_filter_level = s.hand_filter_level = levels;
    }
    const bool weak = frame.time - s.weak_input_time <= options_.weak_input_hold_seconds;
    const bool jittery = frame.time - s.jittery_time <= options_.weak_input_hold_seconds;
    s.joint_filter_level =
        std::clamp(s.joint_filter_level + (weak || jittery ? level_step : -level_step), 0.0f, levels);
    s.hand_filter_level = std::clamp(s.hand_filter_level + (weak ? level_step : -level_step), 0.0f, levels);
    const size_t level = static_cast<size_t>(std::lround(s.joint_filter_level));
    const size_t hand_level = static_cast<size_t>(std::lround(s.hand_filter_level));
    const std::vector<float>& kernel = joint_kernels_[level];
    const int radius = static_cast<int>(kernel.size()) / 2;
    // Frame e + i, within the filter's reach: the segment's edges (and the lag) clamp.
    auto reached = [&](int i) -> const ReconstructedFrame& {
      return s.post[std::clamp(e + i, s.post_first, last) - s.post_first];
    };
    if (radius > 0) {
      const BodyPose& centre = s.post[e - s.post_first].pose;
      const int joints = static_cast<int>(centre.rotations.size());
      std::vector<Eigen::Vector3f> log_sum(joints, Eigen::Vector3f::Zero());
      Eigen::Vector3f pelvis = Eigen::Vector3f::Zero();
      // Where the filter has no frame ahead of the one it emits, the pelvis follows the line
      // through the frames there are (ReconstructionOptions::pelvis_edge_fit): the frame repeated
      // for the taps ahead held a travelling body back. As far as the body travels: where the
      // motion guard held it as standing (the frame before), the line would only carry the
      // solve's hops ahead.
      const float line = options_.motion_guard.enabled ? 1.0f - motion_guard_.standing() : 1.0f;
      const bool fit_pelvis = pelvis_edge_fit_ && e == last && line > 0.0f;
      if (fit_pelvis) LocalLinearWeights(kernel, s.post_first - e, 0, &pelvis_weights);
      for (int i = -radius; i <= radius; ++i) {
        const BodyPose& p = reached(i).pose;
        const float w = kernel[i + radius];
        pelvis += (fit_pelvis ? line * pelvis_weights[i + radius] + (1.0f - line) * w : w) * reached(i).pelvis_position;
        for (int j = 0; j < joints; ++j)
          log_sum[j] += w * RotationVector(Eigen::Quaternionf(centre.rotations[j].conjugate() * p.rotations[j]));
      }
      for (int j = 0; j < joints; ++j)
        frame.pose.rotations[j] = (centre.rotations[j] * FromRotationVector(log_sum[j])).normalized();
      // The pelvis goes to the mean of its positions. (Averaging the root's translation instead
      // moved it wherever the root's rotation differed between the frames: the root can be far
      // from the pelvis — Bandai's joint_Root sits at the capture's origin, metres away — and a
      // turn of a few degrees then swung the body by up to a metre in one frame, issue #22.)
      body.WorldTransforms(frame.pose, &world_rotations, &world_positions);
      frame.pose.root_position += pelvis - world_positions[l.pelvis];
      if (joint_filter_lag_ > 0) {  // a filter that looks ahead eases the feet on and off their pins
        pins.resize(kernel.size());
        for (int side = 0; side < 2; ++side) {
          for (int i = -radius; i <= radius; ++i) {
            const ReconstructedFrame& f = reached(i);
            pins[i + radius] = f.diagnostics.contact[side] ? f.ankle_targets[side] : std::nullopt;
          }
          const std::optional<EasedPin> eased = EasePin(kernel, pins);
          frame.ankle_targets[side].reset();
          if (!eased) continue;
          frame.ankle_targets[side] = eased->target;
          frame.ankle_target_weight[side] = eased->weight;
        }
      }
      ReimposeAnklePins(&frame, &world_rotations, &world_positions);
    }
    // The jump detector takes only input it can trust: a guessed hand travels as the guess does.
    const bool observed =
        s.untracked[e][0] == 0 && s.untracked[e][1] == 0 && s.fading[e][0].weight == 0 && s.fading[e][1].weight == 0;
    for (int side = 0; side < 2; ++side) {  // the step into this frame's input
      auto input_at = [&](int f) { return f >= s.input.first() && f >= 0 ? &s.input[f][side] : nullptr; };
      const bool put_down = s.put_down[e][side];
      const float untracked = s.untracked[e][side];
      if (put_down) {
        frame.hand_state[side] = TrackingState::kPutDown;  // let go: carried with the body (LetGoOfPutDownHands)
      } else if (untracked > options_.max_gap_seconds) {
        frame.hand_state[side] = TrackingState::kLost;  // held by the other hand for long
      } else if (untracked > 0) {
        frame.hand_state[side] = TrackingState::kPredicted;
      } else if (jump_detector_.Step(side, input_at(e - 2), input_at(e - 1), s.input[e][side], observed)) {
        frame.hand_state[side] = TrackingState::kImplausible;
      }
    }
    if (options_.motion_guard.enabled) {
      // The guard moves the whole body rigidly to where the pelvis may go; the hands then reach
      // for the input from there.
      body.WorldTransforms(frame.pose, &world_rotations, &world_positions);
      const Eigen::Vector3f solved = world_positions[l.pelvis];
      // The hands as A2 smoothed them: a noisy tracker's jitter (phone AR's 2-3 cm) is no motion
      // of the hands, and over a stream's first frames it read as metres a second.
      const Eigen::Vector3f hands = WristsMidpoint(s.wrists[e]);
      if (e == 0) {  // a segment's first frame: the hands ahead, as far as they are known
        const int last = std::min(HandsWindowFrames(database_->frame_time(), 0), s.wrists.size() - 1);
        motion_guard_.SetLeadingHands(last * database_->frame_time(),
                                      WristsMidpoint(s.wrists[last]) - WristsMidpoint(s.wrists[0]));
      }
      motion_guard_.SetInputNoise(std::max(jump_detector_.AccelerationNoise(0), jump_detector_.AccelerationNoise(1)));
      // The guard moves the body rigidly, no lower than the joints it rests on allow, as the reach
      // shift (docs/method.md A7).
      const Eigen::Vector3f offset =
          OffsetAboveFloor(motion_guard_.Next(frame.time, solved, hands, &frame.motion_limited) - solved,
                           body.FloorClearance(world_positions));
      frame.pose.root_position += offset;
      // A planted foot stays where it is planted when the body moved a little (the standing
      // filter's centimetres: its legs take the difference); it goes along by as much as the
      // guard held the body back further than a leg can bend for.
      const Eigen::Vector3f foot_offset = PlantedFootOffset(offset, kPlantedFootReach);
      for (int side = 0; side < 2; ++side) {
        if (frame.ankle_targets[side]) *frame.ankle_targets[side] += foot_offset;
      }
      ReimposeAnklePins(&frame, &world_rotations, &world_positions);
    }
    std::optional<SmoothedWrists> hand_target;
    std::array<Eigen::Vector3f, 2> device_points;  // a declared grip's: where the hands' devices are
    std::array<bool, 2> under_floor = {false, false};
    if (options_.hand_target_sigma >= 0.0f) {
      // Hands on the input: a local linear fit over the samples that have arrived, which is the
      // Gaussian average where the window is centred and has no lag where it is one-sided.
      hand_target = FitInput(s, e, hand_kernels_[hand_level]);
      if (s.grip.active()) {  // the device points' wrists, along this body's forearms
        device_points = {hand_target->position[0], hand_target->position[1]};
        body.WorldTransforms(frame.pose, &world_rotations, &world_positions);
        s.grip.ToWrists(body, world_positions, &*hand_target);
      }
      // Input under the floor: no wrist goes lower than over a hand lying on it (hand_floor.h).
      for (int side = 0; side < 2; ++side) {
        float& height = hand_target->position[side].y();
        under_floor[side] = height < -kUnderFloorTolerance;
        height = std::max(height, kLowestWristHeight);
      }
      // Input beyond an arm's reach: the shoulders move towards it, then the torso leans, and
      // where that is not enough the body steps or crouches towards it (reach_lean.h), no faster
      // than a body does.
      const std::array<Eigen::Vector3f, 2> targets = {hand_target->position[0], hand_target->position[1]};
      const std::array<bool, 2> reaching = {frame.hand_state[0] == TrackingState::kTracked,
                                            frame.hand_state[1] == TrackingState::kTracked};
      reach_lean_.MoveCollars(body, targets, reaching, &frame.pose);
      reach_lean_.Apply(body, targets, reaching, database_->frame_time(), &s.reach_turn, &frame.pose);
      // Within the guard's speed bound, with the guard's own motion (issue #22).
      const BodyMotion guarded{motion_guard_.velocity(), motion_guard_.speed_bound()};
      const Eigen::Vector3f shift = reach_lean_.Shift(body, targets, reaching, database_->frame_time(), &s.reach_shift,
                                                      &frame.pose, options_.motion_guard.enabled ? &guarded : nullptr);
      // Planted feet stay on their pins (the legs bend); a free foot the shift pushed into the
      // floor is lifted by the floor rule below.
      if (!shift.isZero()) ReimposeAnklePins(&frame, &world_rotations, &world_positions);
    }
    if (options_.feet_above_floor) KeepFeetAboveFloor(&frame, &world_rotations, &world_positions);
    if (options_.motion_guard.enabled) LimitFootSpeed(s.emitted_feet, &frame, &world_rotations, &world_positions);
    if (hand_target) {
      for (int side = 0; side < 2; ++side) {
        if (s.grip.active() && !under_floor[side]) {  // the forearm reaches the device past the wrist
          SolveLegIk(body, wrist_joints[side], device_points[side], &frame.pose, s.grip.metres());
        } else {
          SolveLegIk(body, wrist_joints[side], hand_target->position[side], &frame.pose);
        }
      }
    }
    body.WorldTransforms(frame.pose, &world_rotations, &world_positions);
    if (s.grip.active()) {
      // The input as wrists: the A2 device points back along the forearms the body holds them with,
      // so that a hand's distance from it is its device's from the input (grip_offset.h).
      SmoothedWrists input = FitInput(s, e, wrist_kernel_.empty() ? hand_kernels_.front() : wrist_kernel_);
      s.grip.ToWrists(body, world_positions, &input);
      frame.wrists = {input.position[0], input.position[1]};
    }
    MarkOutOfReach(s.input[e], under_floor, world_positions, &frame);
    s.emitted_feet = EmittedFeet{frame.time, {world_positions[l.left_ankle], world_positions[l.right_ankle]}};
    frame.pelvis_rotation = world_rotations[l.pelvis];
    frame.pelvis_position = world_positions[l.pelvis];
    frame.index = next_output_index_++;
    out->push_back(std::move(frame));
    ++s.emitted;
    ++statistics_.frames;
    while (s.post_first < s.emitted - widest_radius) {  // older frames no longer reach the filter
      s.post.pop_front();
      ++s.post_first;
    }
  }
  ForgetSettledFrames();
}

void ReconstructionSession::ReimposeAnklePins(ReconstructedFrame* frame,
                                              std::vector<Eigen::Quaternionf>* world_rotations,
                                              std::vector<Eigen::Vector3f>* world_positions) const {
  const BodyModel& body = database_->body();
  const BodyLandmarks& l = database_->rig().topology.landmarks;
  const int ankle_joints[2] = {l.left_ankle, l.right_ankle};
  const auto& targets = frame->ankle_targets;
  const auto& weights = frame->ankle_target_weight;
  // Where the body puts the feet (one leg's IK does not move the other's ankle).
  if ((targets[0] && weights[0] < 1.0f) || (targets[1] && weights[1] < 1.0f))
    body.WorldTransforms(frame->pose, world_rotations, world_positions);
  for (int side = 0; side < 2; ++side) {
    if (!targets[side]) continue;
    Eigen::Vector3f target = *targets[side];
    if (weights[side] < 1.0f) {
      const Eigen::Vector3f& at = (*world_positions)[ankle_joints[side]];
      target = at + weights[side] * (target - at);
    }
    // A leg bent over its pin after the body went down to it (the reach shift's crouch) can fold
    // its knee through the floor (`dance-short` at lag 0: 8 cm under the ground): the floor wins,
    // and the foot comes off its pin as little as keeps the knee above it.
    SolveLegIkKneeAboveFloor(body, ankle_joints[side], target, static_cast<float>(kLowestJointHeight), &frame->pose);
  }
}

void ReconstructionSession::KeepFeetAboveFloor(ReconstructedFrame* frame,
                                               std::vector<Eigen::Quaternionf>* world_rotations,
                                               std::vector<Eigen::Vector3f>* world_positions) const {
  const BodyModel& body = database_->body();
  const BodyLandmarks& l = database_->rig().topology.landmarks;
  const float ground = database_->planted_ankle_height();
  body.WorldTransforms(frame->pose, world_rotations, world_positions);
  for (const int ankle : {l.left_ankle, l.right_ankle}) {
    if (ankle < 0) continue;
    const Eigen::Vector3f at = (*world_positions)[ankle];
    if (at.y() < ground) SolveLegIk(body, ankle, Eigen::Vector3f(at.x(), ground, at.z()), &frame->pose);
  }
}

void ReconstructionSession::LimitFootSpeed(const std::optional<EmittedFeet>& feet, ReconstructedFrame* frame,
                                           std::vector<Eigen::Quaternionf>* world_rotations,
                                           std::vector<Eigen::Vector3f>* world_positions) const {
  const float bound = motion_guard_.foot_speed_bound();
  if (!feet || !std::isfinite(bound)) return;
  // Across a gap (or a new clock) the feet's motion is not known, as the guard's is not on a
  // stream's first frame.
  const double dt = frame->time - feet->time;
  if (!(dt > 0) || dt > 1.5 * database_->frame_time()) return;
  const BodyModel& body = database_->body();
  const BodyLandmarks& l = database_->rig().topology.landmarks;
  const float reach = bound * static_cast<float>(dt);
  body.WorldTransforms(frame->pose, world_rotations, world_positions);
  const std::array<int, 2> ankles = {l.left_ankle, l.right_ankle};
  for (int side = 0; side < 2; ++side) {
    const Eigen::Vector3f& from = feet->ankles[side];
    const Eigen::Vector3f step = (*world_positions)[ankles[side]] - from;
    if (step.norm() <= reach) continue;
    // On the segment from where it was to where the body put it: above the floor as both are.
    SolveLegIkKneeAboveFloor(body, ankles[side], from + step * (reach / step.norm()),
                             static_cast<float>(kLowestJointHeight), &frame->pose);
    frame->motion_limited = true;
  }
}

void ReconstructionSession::MarkOutOfReach(const std::array<Eigen::Vector3f, 2>& input,
                                           const std::array<bool, 2>& under_floor,
                                           const std::vector<Eigen::Vector3f>& world_positions,
                                           ReconstructedFrame* frame) const {
  const BodyLandmarks& l = database_->rig().topology.landmarks;
  const std::array<std::array<int, 3>, 2> arms{
      {{l.left_shoulder, l.left_elbow, l.left_wrist}, {l.right_shoulder, l.right_elbow, l.right_wrist}}};
  for (int side = 0; side < 2; ++side) {
    const auto [shoulder, elbow, wrist] = arms[side];
    if (shoulder < 0 || elbow < 0 || frame->hand_state[side] != TrackingState::kTracked) continue;
    const float reach = (world_positions[elbow] - world_positions[shoulder]).norm() +
                        (world_positions[wrist] - world_positions[elbow]).norm();
    // A device held in the hand reaches its grip offset further (grip_offset.h).
    const float device_reach = kOutOfReachFactor * reach + options_.grip_offset;
    if (under_floor[side] || (input[side] - world_positions[shoulder]).norm() > device_reach) {
      frame->hand_state[side] = TrackingState::kOutOfReach;
    }
  }
}

SmoothedWrists ReconstructionSession::FitInput(const Segment& s, int frame, const std::vector<float>& kernel) const {
  const int first = s.input.first();
  return LocalLinearWrists(s.input.Since(first), frame - first, s.input.size() - 1 - first, kernel,
                           static_cast<float>(1.0 / database_->frame_time()));
}

void ReconstructionSession::ForgetSettledFrames() {
  // Every frame before the oldest one still to be emitted is settled; the stages look back from
  // there by at most one kernel reach (A2 fit, hand target, ankle smoothing) plus one frame (the
  // ankle velocity of the next solve).
  Segment& s = *segment_;
  const int reach =
      static_cast<int>(std::max({wrist_kernel_.size(), hand_kernels_.back().size(), ankle_kernel_.size()})) / 2;
  const int keep_from = s.emitted - reach - 1;
  if (keep_from <= 0) return;
  s.ForEachHistory([keep_from](auto& history) { history.ForgetBefore(keep_from); });
}

absl::Status ReconstructionSession::EndSegment(bool sliced, std::vector<ReconstructedFrame>* out) {
  if (!segment_) return absl::OkStatus();
  if (!segment_->ending) {
    Segment& s = *segment_;
    // The one-sided A2 window at the end, a frame at a time (a window one completes is sliced too).
    while (true) {
      MOCAP_RETURN_IF_ERROR(SolvePending(sliced, out));
      if (s.solved < s.decided) return absl::OkStatus();  // the rest in the next call
      if (s.wrists.size() >= s.input.size()) break;
      MOCAP_RETURN_IF_ERROR(ProcessFrame(out));
    }
    const auto start = Clock::now();
    s.ending = true;  // once the frames decided below are solved (SolvePending)
    if (method_->uses_ankles()) {
      if (options_.mode == StreamMode::kSubInterval && !s.window.empty()) {
        DecideWindow(s);
      } else if (options_.mode == StreamMode::kFixedLag && !s.dp.empty() &&
                 s.dp_first + static_cast<int>(s.dp.size()) > static_cast<int>(s.raw.size())) {
        // The final best path through the frames not decided yet.
        const int t = s.dp_first + static_cast<int>(s.dp.size()) - 1;
        const int decided = static_cast<int>(s.raw.size());
        const std::vector<int> nodes = BestPathFrom(s.dp, s.dp_first, decided);
        for (int f = decided; f <= t; ++f) {
          const AnkleCandidate& c = s.dp[f - s.dp_first].cloud[nodes[f - decided]];
          s.raw.push_back(AnklesOf(c));
          s.raw_rows.push_back(c.row);
        }
      }
      statistics_.path_seconds += SecondsSince(start);
      MOCAP_RETURN_IF_ERROR(
          DecideAnkles(static_cast<int>(s.raw.size()), static_cast<int>(s.raw.size()), {}, true, out));
    }
  }
  return SolvePending(sliced, out);  // ends the segment once its last frames are solved
}

absl::StatusOr<std::vector<ReconstructedFrame>> ReconstructOffline(
    std::shared_ptr<const ReconstructionDatabase> database, const ReconstructionOptions& options,
    const std::vector<WristSample>& samples) {
  MOCAP_ASSIGN_OR_RETURN(std::unique_ptr<ReconstructionSession> session,
                         ReconstructionSession::Create(std::move(database), options));
  std::vector<ReconstructedFrame> frames;
  for (const WristSample& sample : samples) MOCAP_RETURN_IF_ERROR(session->Push(sample, &frames));
  MOCAP_RETURN_IF_ERROR(session->Finish(&frames));
  return frames;
}

}  // namespace mocap

#include "motion/reconstruct/motion_guard.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mocap {
namespace {

// InputJumpDetector: a noise measure needs a few frames; the median norm of a 3-D standard normal.
constexpr int kMinNoiseFrames = 5;
constexpr float kNormalNormMedian = 1.5382f;

// `v` shortened to at most `limit` (unchanged when no limit is known).
Eigen::Vector3f Clamped(const Eigen::Vector3f& v, float limit) {
  const float norm = v.norm();
  if (!(limit > 0) || norm <= limit) return v;
  return v * (limit / norm);
}

float OrUnbounded(float value, float margin) {
  return value > 0 ? value * margin : std::numeric_limits<float>::infinity();
}

}  // namespace

MotionGuard::MotionGuard(const MotionLimits& limits, double frame_time, const MotionGuardOptions& options)
    : frame_time_(frame_time),
      speed_limit_(OrUnbounded(limits.pelvis_speed_max, options.speed_margin)),
      acceleration_limit_(OrUnbounded(limits.pelvis_acceleration_max, options.acceleration_margin)),
      standing_speed_limit_(options.bound_standing_body
                                ? OrUnbounded(limits.pelvis_speed_while_hands_stand, options.beyond_hands_margin)
                                : std::numeric_limits<float>::infinity()),
      hands_limits_(limits),
      standing_smoothing_seconds_(options.standing_smoothing_seconds),
      standing_hands_speed_(options.standing_hands_speed),
      moving_hands_speed_(options.moving_hands_speed),
      standing_window_seconds_(options.standing_window_seconds),
      start_ease_seconds_(options.start_ease_seconds),
      start_rest_seconds_(options.start_rest_seconds),
      standing_noise_acceleration_(options.standing_noise_acceleration),
      standing_noise_max_factor_(options.standing_noise_max_factor),
      bound_window_frames_{HandsWindowFrames(frame_time, 0), HandsWindowFrames(frame_time, 1)},
      hands_(static_cast<size_t>(std::max(bound_window_frames_.back(),
                                          static_cast<int>(std::lround(options.standing_window_seconds / frame_time))) +
                                 1)) {
  // The bounds by the hands' speed, with their margin (none known: unbounded).
  if (!(limits.pelvis_speed_beyond_hands_max > 0)) {
    hands_limits_.pelvis_speed_beyond_hands_max = std::numeric_limits<float>::infinity();
    for (auto& by_hands : hands_limits_.pelvis_speed_by_hands_speed) by_hands.clear();
  }
  hands_limits_.pelvis_speed_beyond_hands_max *= options.beyond_hands_margin;
  for (auto& by_hands : hands_limits_.pelvis_speed_by_hands_speed) {
    for (float& bound : by_hands) bound *= options.beyond_hands_margin;
  }
  // The feet's, alike: the fastest ankle with the speed margin, the bins with the hands' margin.
  hands_limits_.ankle_speed_max = OrUnbounded(limits.ankle_speed_max, options.speed_margin);
  for (auto& by_hands : hands_limits_.ankle_speed_by_hands_speed) {
    if (!(limits.ankle_speed_max > 0)) by_hands.clear();
    for (float& bound : by_hands) bound *= options.beyond_hands_margin;
  }
}

void MotionGuard::SetLeadingHands(double seconds, const Eigen::Vector3f& displacement) {
  pending_leading_ = LeadingSpan{seconds, displacement};
}

Eigen::Vector3f MotionGuard::Next(double time, const Eigen::Vector3f& solved, const Eigen::Vector3f& hands,
                                  bool* limited) {
  *limited = false;
  if (has_previous_ && !(time > previous_time_)) has_previous_ = false;  // a new clock (a reused session)
  const bool continuous = has_previous_ && time - previous_time_ <= 1.5 * frame_time_;
  // The hands' mean speed over the window (as MeasureMotionLimits measures it); none yet at the
  // start of a stream. Across a gap, their mean speed over it: where the hands went while the input
  // was missing is where the body may have gone (reset at the gap, a walk's first frame after
  // it had only a standing body's speed to catch up with).
  if (!has_previous_) {
    hands_.Clear();
    stream_start_ = time;
    leading_ = pending_leading_;
  }
  pending_leading_.reset();  // given for a stream that goes on: its windows know the hands
  const int window = static_cast<int>(hands_.capacity());
  hands_.Push({time, hands});
  // Mean velocity of the midpoint over the last `frames` frames (fewer at a stream's start), and
  // over no more time than they span, but for the sample before a gap.
  auto mean_velocity = [&](int frames) -> Eigen::Vector3f {
    int back = std::min(frames + 1, static_cast<int>(hands_.size()));
    auto sample = [&](int b) -> const HandsSample& { return hands_.Back(static_cast<size_t>(b - 1)); };
    while (back > 2 && time - sample(back).time > (frames + 0.5) * frame_time_) --back;
    const HandsSample& oldest = sample(back);
    return back > 1 ? Eigen::Vector3f((hands - oldest.midpoint) / static_cast<float>(time - oldest.time))
                    : Eigen::Vector3f::Zero();
  };
  std::array<float, kHandsWindowsSeconds.size()> hands_speed;
  for (size_t w = 0; w < hands_speed.size(); ++w) hands_speed[w] = mean_velocity(bound_window_frames_[w]).norm();
  // The shorter window not yet filled since the stream began: over the input ahead, when that
  // spans longer than the frames so far.
  const double since_start = time - stream_start_;
  if (leading_ && since_start < kHandsWindowsSeconds[0] && leading_->seconds > since_start) {
    hands_speed[0] = static_cast<float>(leading_->displacement.norm() / leading_->seconds);
  }
  // Whether the hands stand is read, over a stream's first start_rest_seconds, as if they had
  // stood where first seen until it began: the frames so far alone took a fraction of a second of
  // arm motion for a walk. Over the input ahead instead while that spans longer; not at all where
  // the input ahead spans that long (a whole clip): it says whether the hands travel.
  const bool assume_rest = since_start < start_rest_seconds_ && !(leading_ && leading_->seconds >= start_rest_seconds_);
  const int standing_frames =
      std::min(window - 1, static_cast<int>(std::lround(standing_window_seconds_ / frame_time_)));
  Eigen::Vector3f standing_velocity = mean_velocity(standing_frames);
  if (assume_rest) {
    standing_velocity =
        leading_ && leading_->seconds > since_start
            ? Eigen::Vector3f(leading_->displacement / static_cast<float>(start_rest_seconds_))
            : Eigen::Vector3f(standing_velocity * static_cast<float>(since_start / start_rest_seconds_));
  }
  const float ground_speed = std::hypot(standing_velocity.x(), standing_velocity.z());  // over the ground
  // How far the hands stand: 1 below standing_hands_speed, fading to 0 at moving_hands_speed.
  auto standing_at = [&](float hands_ground_speed) {
    return std::clamp(
        (moving_hands_speed_ - hands_ground_speed) / std::max(1e-3f, moving_hands_speed_ - standing_hands_speed_), 0.0f,
        1.0f);
  };
  const float hands_stand = standing_at(ground_speed);
  Eigen::Vector3f target = solved;
  // How far the body stands: as far as the hands do, and over a stream's first frames as far as
  // the hands ahead stand (all the way when unknown), easing in.
  float standing = hands_stand;
  if (since_start < start_ease_seconds_) {
    const float ahead =
        leading_ && leading_->seconds > 0
            ? standing_at(static_cast<float>(std::hypot(leading_->displacement.x(), leading_->displacement.z()) /
                                             std::max(leading_->seconds, start_rest_seconds_)))
            : 1.0f;
    standing = std::max(standing, ahead * static_cast<float>(1.0 - since_start / start_ease_seconds_));
  }
  standing_ = standing_smoothing_seconds_ > 0 ? standing : 0.0f;
  if (has_previous_ && continuous && standing_smoothing_seconds_ > 0) {
    // Standing: the ground position eases towards the solve (exponential filter, time constant
    // standing_smoothing_seconds), fading out as the hands start to travel.
    const float dt = static_cast<float>(time - previous_time_);
    // Longer for a noisier tracker, whose standing solve hops further.
    const float smoothing =
        standing_smoothing_seconds_ *
        (standing_noise_acceleration_ > 0
             ? std::clamp(input_noise_ / standing_noise_acceleration_, 1.0f, std::max(1.0f, standing_noise_max_factor_))
             : 1.0f);
    const float follow = 1.0f - standing * (1.0f - dt / (smoothing + dt));
    target = previous_target_ + follow * (solved - previous_target_);
  }
  if (!has_previous_) {
    has_previous_ = true;
    has_velocity_ = false;
    previous_time_ = time;
    previous_output_ = previous_target_ = target;
    previous_velocity_.setZero();
    speed_bound_ = foot_speed_bound_ = std::numeric_limits<float>::infinity();
    return target;
  }
  const float dt = static_cast<float>(std::max(time - previous_time_, 0.5 * frame_time_));
  // The velocity before the first step of a stream, or across a gap, is unknown: that step is
  // bounded by speed only.
  const bool velocity_known = has_velocity_ && continuous;
  // The velocity that follows the target: its own motion, plus closing the gap left at the
  // previous frame, at once when it is small, else no faster than one can still brake from
  // (√(2·a·gap) with half the acceleration bound, the other half for following the target).
  const Eigen::Vector3f target_velocity = (target - previous_target_) / dt;
  const Eigen::Vector3f gap = previous_target_ - previous_output_;
  const float gap_length = gap.norm();
  Eigen::Vector3f wanted = target_velocity;
  if (gap_length > 0) {
    const float closing = std::min(gap_length / dt, std::sqrt(acceleration_limit_ * gap_length));
    wanted += gap * (closing / gap_length);
  }
  // A body's bounds: speed (no faster than the database's bodies, nor faster than their pelvis
  // moved while their hands moved as these do), then acceleration. The second always holds, and so does the first: the
  // step from the previous velocity towards one within the speed bound stays within it, unless the bound itself shrank
  // (the hands stopped), when the body brakes as hard as a body can.
  speed_bound_ = std::min(speed_limit_, hands_limits_.PelvisSpeedBoundForHands(hands_speed));
  // While the hands stand, a standing body's bound, fading into the above as they travel.
  if (speed_bound_ > standing_speed_limit_)
    speed_bound_ = standing_speed_limit_ + (1.0f - hands_stand) * (speed_bound_ - standing_speed_limit_);
  foot_speed_bound_ = hands_limits_.AnkleSpeedBoundForHands(hands_speed);
  Eigen::Vector3f velocity = Clamped(wanted, speed_bound_);
  if (velocity_known) velocity = previous_velocity_ + Clamped(velocity - previous_velocity_, acceleration_limit_ * dt);
  Eigen::Vector3f output = previous_output_ + velocity * dt;
  // Within a millimetre: on the target (unless that step would break the acceleration bound).
  const bool snap =
      (output - target).norm() <= 1e-3f &&
      (!velocity_known || ((target - previous_output_) / dt - previous_velocity_).norm() <= acceleration_limit_ * dt);
  if (snap) {
    output = target;
  } else {
    *limited = true;
  }
  previous_velocity_ = (output - previous_output_) / dt;
  has_velocity_ = true;
  previous_time_ = time;
  previous_output_ = output;
  previous_target_ = target;
  return output;
}

InputJumpDetector::InputJumpDetector(const MotionLimits& limits, double frame_time, const MotionGuardOptions& options)
    : rate_(static_cast<float>(1.0 / frame_time)),
      speed_limit_(OrUnbounded(limits.wrist_speed_max, options.input_speed_margin)),
      acceleration_limit_(OrUnbounded(limits.wrist_acceleration_max, options.input_acceleration_margin)),
      sigmas_(options.input_noise_sigmas) {
  const int window =
      std::max(kMinNoiseFrames, static_cast<int>(std::lround(options.input_noise_window_seconds / frame_time)));
  for (RecentValues<float>& noise : noise_) noise.Resize(static_cast<size_t>(window));
  scratch_.reserve(static_cast<size_t>(window));
}

float InputJumpDetector::AccelerationNoise(int side) const {
  const RecentValues<float>& noise = noise_[static_cast<size_t>(side)];
  if (sigmas_ <= 0.0f || static_cast<int>(noise.size()) < kMinNoiseFrames) return 0.0f;
  scratch_.assign(noise.Unordered().begin(), noise.Unordered().end());
  const auto middle = scratch_.begin() + static_cast<long>(noise.size() / 2);
  std::nth_element(scratch_.begin(), middle, scratch_.end());
  return *middle / kNormalNormMedian;
}

bool InputJumpDetector::Step(int side, const Eigen::Vector3f* before_previous, const Eigen::Vector3f* previous,
                             const Eigen::Vector3f& current, bool observed) {
  if (previous == nullptr) return false;
  // Until the hand's noise is measured (its first frames) nothing is judged: a noisy device's
  // first steps would be read as jumps.
  const bool measured =
      sigmas_ <= 0.0f || static_cast<int>(noise_[static_cast<size_t>(side)].size()) >= kMinNoiseFrames;
  // White noise of `acceleration_noise` per axis in second differences is √3 / frame rate of it
  // per axis in first differences (√2 σ rate against √6 σ rate²).
  const float acceleration_noise = AccelerationNoise(side);
  const float speed_noise = acceleration_noise / (std::sqrt(3.0f) * rate_);
  const Eigen::Vector3f velocity = (current - *previous) * rate_;
  // The database's bound and the noise's allowance add as independent errors do: a hand at its
  // hardest and the noise at `sigmas_` along it, both rare, rarely meet (in a line, a controller's
  // 20 cm step would hide in a 5 mm tracker's noise beside a database of fast dances).
  const bool too_fast = measured && velocity.norm() > std::hypot(speed_limit_, sigmas_ * speed_noise);
  if (before_previous == nullptr) return too_fast;
  const float acceleration = (velocity - (*previous - *before_previous) * rate_).norm() * rate_;
  if (observed) noise_[static_cast<size_t>(side)].Push(acceleration);
  return too_fast || (measured && acceleration > std::hypot(acceleration_limit_, sigmas_ * acceleration_noise));
}

Eigen::Vector3f PlantedFootOffset(const Eigen::Vector3f& body_offset, float leg_give) {
  const float norm = body_offset.norm();
  return norm > leg_give ? Eigen::Vector3f((1.0f - leg_give / norm) * body_offset) : Eigen::Vector3f::Zero();
}

Eigen::Vector3f OffsetAboveFloor(const Eigen::Vector3f& body_offset, float floor_clearance) {
  Eigen::Vector3f offset = body_offset;
  if (offset.y() < 0.0f) offset.y() = std::max(offset.y(), std::min(0.0f, -floor_clearance));
  return offset;
}

}  // namespace mocap

#include "motion/reconstruct/plausibility.h"

#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "motion/reconstruct/hand_floor.h"

namespace mocap {
namespace {

Eigen::Vector3f Vec(const float v[3]) { return {v[0], v[1], v[2]}; }

float Percentile(std::vector<float> values, double q) {
  if (values.empty()) return 0.0f;
  const size_t k = std::min(values.size() - 1, static_cast<size_t>(q * static_cast<double>(values.size())));
  std::nth_element(values.begin(), values.begin() + static_cast<long>(k), values.end());
  return values[k];
}

constexpr double kEnvelopeQuantile = 0.9999;
constexpr size_t kEnvelopeMinFrames = 10000;

float Max(const std::vector<float>& values) {
  return values.empty() ? 0.0f : *std::max_element(values.begin(), values.end());
}

// A bin's pelvis speed bound: the fastest but for the bin's outliers. A bin holds hundreds to
// hundreds of thousands of frames, and as their maximum a single frame (a jump, a marker swap)
// set the bound of a standing body's hands at 1.5 m/s. With fewer than kEnvelopeMinFrames
// frames, the fastest.
float EnvelopeSpeed(std::vector<float> speeds) {
  if (speeds.size() < kEnvelopeMinFrames) return Max(speeds);
  return Percentile(std::move(speeds), kEnvelopeQuantile);
}

// Each bin's EnvelopeSpeed, never less than the bin's before it (a faster body's bound holds a
// slower one's).
std::vector<float> RunningEnvelopes(std::vector<std::vector<float>> bins) {
  std::vector<float> envelopes(bins.size(), 0.0f);
  for (size_t bin = 0; bin < bins.size(); ++bin) {
    envelopes[bin] = EnvelopeSpeed(std::move(bins[bin]));
    if (bin > 0) envelopes[bin] = std::max(envelopes[bin], envelopes[bin - 1]);
  }
  return envelopes;
}

}  // namespace

int HandsWindowFrames(double frame_time, int w) {
  return std::max(1, static_cast<int>(std::lround(kHandsWindowsSeconds[w] / frame_time)));
}

MotionLimits MeasureMotionLimits(std::span<const std::span<const FrameFeatures>> clips, double frame_time) {
  const float rate = static_cast<float>(1.0 / frame_time);
  std::vector<float> pelvis_speed, pelvis_acceleration, wrist_acceleration;
  MotionLimits limits;
  limits.pelvis_speed_beyond_hands_max = -std::numeric_limits<float>::infinity();
  std::vector<float> standing_pelvis_speed;  // frames whose hands stand
  const int standing_frames = std::max(1, static_cast<int>(std::lround(kStandingWindowSeconds / frame_time)));
  // Per window and hands' speed bin: the pelvis' speeds, and the faster ankle's.
  std::array<std::vector<std::vector<float>>, kHandsWindowsSeconds.size()> speeds_by_hands, ankle_speeds_by_hands;
  for (std::span<const FrameFeatures> clip : clips) {
    std::vector<Eigen::Vector3f> midpoints;
    Eigen::Vector3f previous_pelvis = Eigen::Vector3f::Zero(), previous_velocity = Eigen::Vector3f::Zero();
    std::array<Eigen::Vector3f, 2> previous_wrist_velocity{};
    for (size_t f = 0; f < clip.size(); ++f) {
      const ReferenceFrame ref = ReferenceFrameOf(clip[f]);
      const Eigen::Matrix3f& rotation = ref.rotation;
      const Eigen::Vector3f pelvis = ref.origin + rotation * Vec(clip[f].pelvis_position);
      midpoints.push_back(ref.origin +
                          rotation * (0.5f * (Vec(clip[f].wrist_position[0]) + Vec(clip[f].wrist_position[1]))));
      std::array<Eigen::Vector3f, 2> wrist_velocity;
      for (int side = 0; side < 2; ++side) wrist_velocity[side] = rotation * Vec(clip[f].wrist_velocity[side]);
      // Frame 0's velocities are the forward difference (= frame 1's): start at frame 1.
      if (f >= 1) {
        const Eigen::Vector3f velocity = (pelvis - previous_pelvis) * rate;
        pelvis_speed.push_back(velocity.norm());
        const int back = std::min(standing_frames, static_cast<int>(f));
        const Eigen::Vector3f travel = midpoints[f] - midpoints[f - back];
        if (std::hypot(travel.x(), travel.z()) * rate / static_cast<float>(back) < kStandingHandsSpeed)
          standing_pelvis_speed.push_back(velocity.norm());
        for (size_t w = 0; w < kHandsWindowsSeconds.size(); ++w) {
          const int frames = std::min<int>(HandsWindowFrames(frame_time, static_cast<int>(w)), static_cast<int>(f));
          const float speed = (midpoints[f] - midpoints[f - frames]).norm() * rate / static_cast<float>(frames);
          if (w == 0) {
            limits.pelvis_speed_beyond_hands_max =
                std::max(limits.pelvis_speed_beyond_hands_max, velocity.norm() - speed);
          }
          const size_t bin = static_cast<size_t>(speed / MotionLimits::kHandsSpeedBin);
          for (auto* by_hands : {&speeds_by_hands[w], &ankle_speeds_by_hands[w]}) {
            if (bin >= by_hands->size()) by_hands->resize(bin + 1);
          }
          speeds_by_hands[w][bin].push_back(velocity.norm());
          ankle_speeds_by_hands[w][bin].push_back(
              std::max(Vec(clip[f].ankle_velocity[0]).norm(), Vec(clip[f].ankle_velocity[1]).norm()));
        }
        for (int side = 0; side < 2; ++side) {
          limits.wrist_speed_max = std::max(limits.wrist_speed_max, wrist_velocity[side].norm());
          limits.ankle_speed_max = std::max(limits.ankle_speed_max, Vec(clip[f].ankle_velocity[side]).norm());
        }
        if (f >= 2) {
          pelvis_acceleration.push_back((velocity - previous_velocity).norm() * rate);
          for (int side = 0; side < 2; ++side)
            wrist_acceleration.push_back((wrist_velocity[side] - previous_wrist_velocity[side]).norm() * rate);
        }
        previous_velocity = velocity;
      }
      previous_pelvis = pelvis;
      previous_wrist_velocity = wrist_velocity;
    }
  }
  if (pelvis_speed.empty()) limits.pelvis_speed_beyond_hands_max = 0;
  for (size_t w = 0; w < kHandsWindowsSeconds.size(); ++w) {
    limits.pelvis_speed_by_hands_speed[w] = RunningEnvelopes(std::move(speeds_by_hands[w]));
    limits.ankle_speed_by_hands_speed[w] = RunningEnvelopes(std::move(ankle_speeds_by_hands[w]));
  }
  limits.pelvis_speed_while_hands_stand = EnvelopeSpeed(std::move(standing_pelvis_speed));
  limits.pelvis_speed_p99 = Percentile(pelvis_speed, 0.99);
  limits.pelvis_speed_max = Max(pelvis_speed);
  limits.pelvis_acceleration_p99 = Percentile(pelvis_acceleration, 0.99);
  limits.pelvis_acceleration_max = Max(pelvis_acceleration);
  limits.wrist_acceleration_p99 = Percentile(wrist_acceleration, 0.99);
  limits.wrist_acceleration_max = Max(wrist_acceleration);
  return limits;
}

namespace {

// The smallest of `bound` and each window's bin for the hands' speed over that window (a window
// past its last bin bounds nothing).
float WithinBins(float bound, const std::array<std::vector<float>, kHandsWindowsSeconds.size()>& bins,
                 const std::array<float, kHandsWindowsSeconds.size()>& hands_speed) {
  for (size_t w = 0; w < hands_speed.size(); ++w) {
    const size_t bin = static_cast<size_t>(std::max(0.0f, hands_speed[w]) / MotionLimits::kHandsSpeedBin);
    if (bin < bins[w].size()) bound = std::min(bound, bins[w][bin]);
  }
  return bound;
}

}  // namespace

float MotionLimits::PelvisSpeedBoundForHands(const std::array<float, kHandsWindowsSeconds.size()>& hands_speed) const {
  return WithinBins(hands_speed[0] + pelvis_speed_beyond_hands_max, pelvis_speed_by_hands_speed, hands_speed);
}

float MotionLimits::AnkleSpeedBoundForHands(const std::array<float, kHandsWindowsSeconds.size()>& hands_speed) const {
  return WithinBins(ankle_speed_max, ankle_speed_by_hands_speed, hands_speed);
}

PlausibilityRig MakePlausibilityRig(const Skeleton& skeleton, const BodyLandmarks& landmarks) {
  PlausibilityRig rig;
  rig.pelvis = landmarks.pelvis;
  rig.wrists = {landmarks.left_wrist, landmarks.right_wrist};
  rig.ankles = {landmarks.left_ankle, landmarks.right_ankle};
  const std::array<int, 2> shoulders = {landmarks.left_shoulder, landmarks.right_shoulder};
  for (int side = 0; side < 2; ++side) {
    int shoulder = shoulders[side];
    if (shoulder < 0) {  // older rigs: wrist → elbow → shoulder joint
      shoulder = rig.wrists[side];
      for (int up = 0; up < 2 && shoulder >= 0 && skeleton.parent(shoulder) >= 0; ++up)
        shoulder = skeleton.parent(shoulder);
    }
    rig.shoulders[side] = shoulder;
    float reach = 0.0f;
    for (int j = rig.wrists[side]; j >= 0 && j != shoulder; j = skeleton.parent(j))
      reach += skeleton.joint(j).offset.norm();
    rig.arm_reach[side] = reach;
  }
  std::vector<bool> above_pelvis(skeleton.num_joints(), false);
  if (rig.pelvis >= 0) {
    for (int j = skeleton.parent(rig.pelvis); j >= 0; j = skeleton.parent(j)) above_pelvis[j] = true;
  }
  for (int j = 0; j < skeleton.num_joints(); ++j) {
    if (!above_pelvis[j]) rig.body_joints.push_back(j);
  }
  return rig;
}

PlausibilityFrame MakePlausibilityFrame(const PlausibilityRig& rig, std::span<const Eigen::Vector3f> joints,
                                        const std::array<Eigen::Vector3f, 2>& input, double time, int segment,
                                        bool flagged, bool motion_limited) {
  PlausibilityFrame frame;
  frame.time = time;
  frame.segment = segment;
  frame.pelvis = joints[rig.pelvis];
  frame.input = input;
  frame.flagged = flagged;
  frame.motion_limited = motion_limited;
  for (int side = 0; side < 2; ++side) {
    frame.hands[side] = joints[rig.wrists[side]];
    frame.ankles[side] = joints[rig.ankles[side]];
    // A centimetre of slack: a straight arm's wrist is exactly at its reach. No hand reaches under
    // the floor (hand_floor.h).
    frame.input_in_reach[side] = (input[side] - joints[rig.shoulders[side]]).norm() <= rig.arm_reach[side] + 0.01f &&
                                 input[side].y() >= -kUnderFloorTolerance;
  }
  frame.lowest_point = std::numeric_limits<float>::infinity();
  for (int j : rig.body_joints) frame.lowest_point = std::min(frame.lowest_point, joints[j].y());
  return frame;
}

void Histogram::Add(float value) {
  value = std::max(0.0f, value);
  ++bins_[static_cast<long>(std::floor(value / bin_width_))];
  ++count_;
  max_ = std::max(max_, value);
}

void Histogram::Merge(const Histogram& other) {
  for (const auto& [bin, count] : other.bins_) bins_[bin] += count;
  count_ += other.count_;
  max_ = std::max(max_, other.max_);
}

float Histogram::Quantile(double q) const {
  if (count_ == 0) return 0.0f;
  const double wanted = std::clamp(q, 0.0, 1.0) * static_cast<double>(count_);
  long seen = 0;
  for (const auto& [bin, count] : bins_) {
    seen += count;
    if (static_cast<double>(seen) >= wanted) return std::min(max_, static_cast<float>(bin + 1) * bin_width_);
  }
  return max_;
}

double Histogram::FractionBelow(float value) const {
  if (count_ == 0) return 1.0;
  const long last = static_cast<long>(std::floor(std::max(0.0f, value) / bin_width_));
  long below = 0;
  for (const auto& [bin, count] : bins_) {
    if (bin > last) break;
    below += count;
  }
  return static_cast<double>(below) / static_cast<double>(count_);
}

void PlausibilityStats::Merge(const PlausibilityStats& o) {
  frames += o.frames;
  pelvis_speed.Merge(o.pelvis_speed);
  pelvis_acceleration_max = std::max(pelvis_acceleration_max, o.pelvis_acceleration_max);
  frames_over_speed_limit += o.frames_over_speed_limit;
  ankle_speed.Merge(o.ankle_speed);
  hand_distance.Merge(o.hand_distance);
  hand_frames_out_of_reach += o.hand_frames_out_of_reach;
  hand_distance_out_of_reach_max = std::max(hand_distance_out_of_reach_max, o.hand_distance_out_of_reach_max);
  lower_foot_height.Merge(o.lower_foot_height);
  penetration_max = std::max(penetration_max, o.penetration_max);
  penetrating_frames += o.penetrating_frames;
  flagged_frames += o.flagged_frames;
  motion_limited_frames += o.motion_limited_frames;
  put_down_hand_frames += o.put_down_hand_frames;
}

PlausibilityStats MeasurePlausibility(std::span<const PlausibilityFrame> frames, float planted_ankle_height,
                                      float speed_limit) {
  PlausibilityStats stats;
  for (size_t i = 0; i < frames.size(); ++i) {
    const PlausibilityFrame& f = frames[i];
    ++stats.frames;
    stats.flagged_frames += f.flagged;
    stats.motion_limited_frames += f.motion_limited;
    stats.put_down_hand_frames += f.put_down_hands;
    if (i >= 1 && f.time > frames[i - 1].time) {
      // Across a gap too: a body that reappears far away has moved that fast.
      const PlausibilityFrame& p = frames[i - 1];
      const double dt = f.time - p.time;
      const float speed = static_cast<float>((f.pelvis - p.pelvis).norm() / dt);
      stats.pelvis_speed.Add(speed);
      if (speed_limit > 0 && speed > speed_limit) ++stats.frames_over_speed_limit;
      for (int side = 0; side < 2; ++side)
        stats.ankle_speed.Add(static_cast<float>((f.ankles[side] - p.ankles[side]).norm() / dt));
      if (i >= 2 && p.segment == f.segment && frames[i - 2].segment == f.segment && p.time > frames[i - 2].time) {
        const PlausibilityFrame& q = frames[i - 2];
        const Eigen::Vector3d v1 = (p.pelvis - q.pelvis).cast<double>() / (p.time - q.time);
        const Eigen::Vector3d v2 = (f.pelvis - p.pelvis).cast<double>() / dt;
        stats.pelvis_acceleration_max =
            std::max(stats.pelvis_acceleration_max, static_cast<float>((v2 - v1).norm() / (0.5 * (f.time - q.time))));
      }
    }
    for (int side = 0; side < 2; ++side) {
      const float distance = (f.hands[side] - f.input[side]).norm();
      if (f.input_in_reach[side]) {
        stats.hand_distance.Add(distance);
      } else {
        ++stats.hand_frames_out_of_reach;
        stats.hand_distance_out_of_reach_max = std::max(stats.hand_distance_out_of_reach_max, distance);
      }
    }
    stats.lower_foot_height.Add(std::min(f.ankles[0].y(), f.ankles[1].y()) - planted_ankle_height);
    if (f.lowest_point < 0.0f) {
      stats.penetration_max = std::max(stats.penetration_max, -f.lowest_point);
      if (f.lowest_point < -0.01f) ++stats.penetrating_frames;
    }
  }
  return stats;
}

}  // namespace mocap

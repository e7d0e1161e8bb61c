#include "motion/reconstruct/footskate_cleanup.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "motion/reconstruct/plausibility.h"
#include "motion/skeleton/two_bone_ik.h"

namespace mocap {

void SolveLegIk(const BodyModel& body, int ankle_joint, const Eigen::Vector3f& target, BodyPose* pose, float beyond) {
  const Skeleton& skeleton = body.skeleton();
  const int knee = skeleton.parent(ankle_joint);
  const int hip = knee >= 0 ? skeleton.parent(knee) : -1;
  if (hip < 0) return;
  std::vector<Eigen::Quaternionf> rotations;
  std::vector<Eigen::Vector3f> positions;
  body.WorldTransforms(*pose, &rotations, &positions);
  const Eigen::Vector3f lower = positions[ankle_joint] - positions[knee];
  const Eigen::Vector3f end = beyond > 0.0f && lower.norm() > 1e-6f
                                  ? Eigen::Vector3f(positions[ankle_joint] + beyond * lower.normalized())
                                  : positions[ankle_joint];
  // Straight leg: any bend axis.
  const TwoBoneTurns turns =
      SolveTwoBoneIk(positions[hip], positions[knee], end, target, rotations[knee] * Eigen::Vector3f::UnitX());
  const Eigen::Quaternionf& hip_turn = turns.root_turn;
  const Eigen::Quaternionf& knee_turn = turns.middle_turn;
  const Eigen::Quaternionf ankle_world = rotations[ankle_joint];
  pose->rotations[hip] = (pose->rotations[hip] * (rotations[hip].conjugate() * hip_turn * rotations[hip])).normalized();
  pose->rotations[knee] =
      (pose->rotations[knee] * (rotations[knee].conjugate() * knee_turn * rotations[knee])).normalized();
  const Eigen::Quaternionf new_knee_world = hip_turn * knee_turn * rotations[knee];
  pose->rotations[ankle_joint] = (new_knee_world.conjugate() * ankle_world).normalized();
}

float SolveLegIkKneeAboveFloor(const BodyModel& body, int ankle_joint, const Eigen::Vector3f& target, float knee_floor,
                               BodyPose* pose) {
  const Skeleton& skeleton = body.skeleton();
  const int knee = skeleton.parent(ankle_joint);
  const int hip = knee >= 0 ? skeleton.parent(knee) : -1;
  if (hip < 0) return 0.0f;
  std::vector<Eigen::Quaternionf> rotations;
  std::vector<Eigen::Vector3f> positions;
  body.WorldTransforms(*pose, &rotations, &positions);
  const Eigen::Vector3f from = positions[ankle_joint];
  const float floor = std::min(knee_floor, positions[knee].y());  // a knee already under goes no lower
  const std::array<Eigen::Quaternionf, 3> leg = {pose->rotations[hip], pose->rotations[knee],
                                                 pose->rotations[ankle_joint]};
  auto knee_stays_up = [&](float part) {  // solves from the leg as it was
    pose->rotations[hip] = leg[0];
    pose->rotations[knee] = leg[1];
    pose->rotations[ankle_joint] = leg[2];
    if (part > 0.0f) SolveLegIk(body, ankle_joint, from + part * (target - from), pose);
    body.WorldTransforms(*pose, &rotations, &positions);
    return positions[knee].y() >= floor;
  };
  if (knee_stays_up(1.0f)) return 1.0f;
  float kept = 0.0f;
  float step = 0.5f;
  for (int iteration = 0; iteration < 6; ++iteration, step *= 0.5f) {
    if (knee_stays_up(kept + step)) kept += step;
  }
  knee_stays_up(kept);
  return kept;
}

FootskateCleaner::FootskateCleaner(const BodyModel& body, float planted_ankle_height, double frame_time,
                                   const FootskateOptions& options, bool streaming)
    : body_(body),
      planted_height_(planted_ankle_height),
      rate_(static_cast<float>(1.0 / frame_time)),
      options_(options),
      hold_frames_(streaming ? std::clamp(static_cast<int>(std::lround(options.stream_hold_seconds * rate_)), 0,
                                          static_cast<int>(Foot::kRecentFrames) - 1)
                             : 0),
      pin_at_mean_(streaming && options.stream_pin_at_mean) {}

void FootskateCleaner::Reset() { feet_ = {}; }

std::array<bool, 2> PlantedFeet(const DatabaseFrame& frame, float planted_ankle_height,
                                const FootskateOptions& options) {
  std::array<bool, 2> planted{};
  for (int side = 0; side < 2; ++side) {
    // Velocities are in the wrist reference frame, whose y axis is up: x and z span the ground.
    const float* v = frame.ankle_velocity[side];
    planted[side] = std::hypot(v[0], v[2]) < options.contact_speed &&
                    frame.ankle_position[side][1] < planted_ankle_height + options.contact_height;
  }
  return planted;
}

bool EstimateSaysPlanted(const Eigen::Vector3f& previous, const Eigen::Vector3f& estimate, float planted_ankle_height,
                         float rate, const FootskateOptions& options) {
  const Eigen::Vector2f step(estimate.x() - previous.x(), estimate.z() - previous.z());
  return step.norm() * rate < options.contact_speed && estimate.y() < planted_ankle_height + options.contact_height;
}

void PlantAnkleContacts(std::span<std::array<Eigen::Vector3f, 2>> ankles, const std::array<Eigen::Vector3f, 2>* before,
                        bool segment_ends, float planted_ankle_height, double frame_time,
                        const FootskateOptions& options, const StandingHands& standing) {
  const int n = static_cast<int>(ankles.size());
  const float rate = static_cast<float>(1.0 / frame_time);
  const int ease = options.release_frames;
  const float min_frames = options.plant_min_seconds * rate;
  // A contact must fit whole: a fixed lag's one frame at a time returns here, allocating nothing.
  if (options.plant_min_seconds <= 0 || n == 0 || static_cast<float>(n) < min_frames) return;
  auto planted = [&](const Eigen::Vector3f& previous, const Eigen::Vector3f& estimate) {
    return EstimateSaysPlanted(previous, estimate, planted_ankle_height, rate, options);
  };
  // Whether the body stands about the gap [gap_begin, gap_end): the hands' mean ground velocity
  // over the window centred on it (clipped to the stretch).
  const int half_window = std::max(1, HandsWindowFrames(frame_time, 1) / 2);
  auto stands_about = [&](int gap_begin, int gap_end) {
    if (static_cast<int>(standing.midpoints.size()) != n) return false;
    const int centre = (gap_begin + gap_end) / 2;
    const int low = std::max(0, centre - half_window), high = std::min(n - 1, centre + half_window);
    if (high <= low) return false;
    const float seconds = static_cast<float>((high - low) * frame_time);
    return (standing.midpoints[high] - standing.midpoints[low]).norm() < standing.speed * seconds;
  };
  for (int side = 0; side < 2; ++side) {
    auto contact_at = [&](int f) {
      if (f > 0) return planted(ankles[f - 1][side], ankles[f][side]);
      return before != nullptr && planted((*before)[side], ankles[0][side]);
    };
    // The contacts first, from the unchanged estimates, then their offsets.
    std::vector<std::pair<int, int>> contacts;  // [begin, end) frames
    for (int f = 0; f < n;) {
      if (!contact_at(f)) {
        ++f;
        continue;
      }
      const int begin = f;
      while (f < n && contact_at(f)) ++f;
      if (!contacts.empty()) {
        const int gap_begin = contacts.back().second;
        const bool lifted = std::any_of(ankles.begin() + gap_begin, ankles.begin() + begin, [&](const auto& frame) {
          return frame[side].y() >= planted_ankle_height + options.contact_height;
        });
        if (!lifted && stands_about(gap_begin, begin)) {
          contacts.back().second = f;
          continue;
        }
      }
      contacts.emplace_back(begin, f);
    }
    std::vector<Eigen::Vector3f> offset(n, Eigen::Vector3f::Zero());
    for (const auto& [begin, end] : contacts) {
      const bool began_inside = begin > 0 || before == nullptr;
      const bool eased_inside = (begin >= ease || before == nullptr) && (end + ease <= n || segment_ends);
      if (!began_inside || (end == n && !segment_ends) || !eased_inside) continue;
      if (static_cast<float>(end - begin) < min_frames) continue;
      Eigen::Vector3f mean = Eigen::Vector3f::Zero();
      for (int f = begin; f < end; ++f) mean += ankles[f][side];
      mean /= static_cast<float>(end - begin);
      for (int f = begin; f < end; ++f) offset[f] = mean - ankles[f][side];
      for (int k = 1; k <= ease; ++k) {  // linear ease, as the cleanup's release
        const float fraction = static_cast<float>(ease + 1 - k) / static_cast<float>(ease + 1);
        if (begin - k >= 0) offset[begin - k] += fraction * offset[begin];
        if (end - 1 + k < n) offset[end - 1 + k] += fraction * offset[end - 1];
      }
    }
    for (int f = 0; f < n; ++f) ankles[f][side] += offset[f];
  }
}

std::optional<EasedPin> EasePin(std::span<const float> kernel, std::span<const std::optional<Eigen::Vector3f>> pins) {
  float total = 0, planted = 0;
  Eigen::Vector3f sum = Eigen::Vector3f::Zero();
  for (size_t i = 0; i < kernel.size() && i < pins.size(); ++i) {
    const float w = std::max(0.0f, kernel[i]);
    total += w;
    if (!pins[i]) continue;
    planted += w;
    sum += w * *pins[i];
  }
  if (!(planted > 0)) return std::nullopt;
  return EasedPin{.target = sum / planted, .weight = std::min(1.0f, planted / total)};
}

Eigen::Vector3f FootskateCleaner::ReleaseTarget(const Foot& foot, const Eigen::Vector3f& solved) const {
  const float fraction = static_cast<float>(foot.release_left) / static_cast<float>(options_.release_frames + 1);
  return solved + fraction * foot.release_offset;
}

bool FootskateCleaner::StillPlanted(const Foot& foot, const Eigen::Vector3f& estimate) const {
  const size_t span = std::min(static_cast<size_t>(hold_frames_), foot.recent.size());
  return EstimateSaysPlanted(foot.recent.Back(span - 1), estimate, planted_height_, rate_ / static_cast<float>(span),
                             options_);
}

std::array<bool, 2> FootskateCleaner::Process(const std::array<Eigen::Vector3f, 2>& estimated_ankles,
                                              const DatabaseFrame* source_frame, BodyPose* pose,
                                              AnkleTargets* targets) {
  std::array<bool, 2> contact{false, false};
  if (targets) *targets = {};
  const BodyLandmarks& l = body_.rig().topology.landmarks;
  const int ankle_joints[2] = {l.left_ankle, l.right_ankle};
  const bool use_database = source_frame != nullptr && options_.contact_source != ContactSource::kEstimatedAnkles;
  const bool use_estimate = source_frame == nullptr || options_.contact_source != ContactSource::kDatabaseFrame;
  const std::array<bool, 2> database =
      use_database ? PlantedFeet(*source_frame, planted_height_, options_) : std::array<bool, 2>{true, true};
  for (int side = 0; side < 2; ++side) {
    Foot& foot = feet_[side];
    const Eigen::Vector3f& estimate = estimated_ankles[side];
    bool estimated = true;
    if (use_estimate) {
      estimated = foot.planted && hold_frames_ > 0
                      ? StillPlanted(foot, estimate)
                      : !foot.recent.empty() &&
                            EstimateSaysPlanted(foot.recent.Back(0), estimate, planted_height_, rate_, options_);
    }
    contact[side] = database[side] && estimated;
    foot.recent.Push(estimate);
    if (!options_.enabled) continue;
    body_.WorldTransforms(*pose, &rotations_, &positions_);
    const Eigen::Vector3f solved = positions_[ankle_joints[side]];
    if (contact[side]) {
      if (!foot.planted) {
        // A contact that begins while the last one's release is under way begins where the foot
        // is: part of the way back to its last pin, not where this frame's solve put the ankle.
        foot.pin = foot.release_left > 0 && options_.resume_where_released ? ReleaseTarget(foot, solved) : solved;
        foot.contact_start_estimate = estimate;
        foot.contact_estimate_sum.setZero();
        foot.contact_frames = 0;
      }
      foot.planted = true;
      foot.release_left = 0;
      if (pin_at_mean_) {
        // Where the contact began, moved along the ground by how far the estimate's mean over the
        // contact lies from its first frame.
        foot.contact_estimate_sum += estimate;
        ++foot.contact_frames;
        const Eigen::Vector3f mean = foot.contact_estimate_sum / static_cast<float>(foot.contact_frames);
        foot.current_pin = foot.pin + Eigen::Vector3f(mean.x() - foot.contact_start_estimate.x(), 0.0f,
                                                      mean.z() - foot.contact_start_estimate.z());
      } else {
        foot.current_pin = foot.pin;
      }
      SolveLegIk(body_, ankle_joints[side], foot.current_pin, pose);
      if (targets) (*targets)[side] = foot.current_pin;
      continue;
    }
    if (foot.planted) {
      foot.planted = false;
      foot.release_offset = foot.current_pin - solved;
      foot.release_left = options_.release_frames;
    }
    if (foot.release_left > 0) {
      const Eigen::Vector3f target = ReleaseTarget(foot, solved);
      SolveLegIk(body_, ankle_joints[side], target, pose);
      if (targets) (*targets)[side] = target;
      --foot.release_left;
    }
  }
  return contact;
}

}  // namespace mocap

#include "motion/reconstruct/footskate_cleanup.h"

#include <algorithm>
#include <cmath>

#include "motion/skeleton/two_bone_ik.h"

namespace mocap {

void SolveLegIk(const BodyModel& body, int ankle_joint, const Eigen::Vector3f& target, BodyPose* pose) {
  const Skeleton& skeleton = body.skeleton();
  const int knee = skeleton.parent(ankle_joint);
  const int hip = knee >= 0 ? skeleton.parent(knee) : -1;
  if (hip < 0) return;
  std::vector<Eigen::Quaternionf> rotations;
  std::vector<Eigen::Vector3f> positions;
  body.WorldTransforms(*pose, &rotations, &positions);
  // Straight leg: any bend axis.
  const TwoBoneTurns turns = SolveTwoBoneIk(positions[hip], positions[knee], positions[ankle_joint], target,
                                            rotations[knee] * Eigen::Vector3f::UnitX());
  const Eigen::Quaternionf& hip_turn = turns.root_turn;
  const Eigen::Quaternionf& knee_turn = turns.middle_turn;
  const Eigen::Quaternionf ankle_world = rotations[ankle_joint];
  pose->rotations[hip] = (pose->rotations[hip] * (rotations[hip].conjugate() * hip_turn * rotations[hip])).normalized();
  pose->rotations[knee] =
      (pose->rotations[knee] * (rotations[knee].conjugate() * knee_turn * rotations[knee])).normalized();
  const Eigen::Quaternionf new_knee_world = hip_turn * knee_turn * rotations[knee];
  pose->rotations[ankle_joint] = (new_knee_world.conjugate() * ankle_world).normalized();
}

FootskateCleaner::FootskateCleaner(const BodyModel& body, float planted_ankle_height, double frame_time,
                                   const FootskateOptions& options)
    : body_(body),
      planted_height_(planted_ankle_height),
      rate_(static_cast<float>(1.0 / frame_time)),
      options_(options) {}

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

bool FootskateCleaner::EstimateSaysPlanted(const Eigen::Vector3f& previous, const Eigen::Vector3f& estimate) const {
  const Eigen::Vector2f step(estimate.x() - previous.x(), estimate.z() - previous.z());
  return step.norm() * rate_ < options_.contact_speed && estimate.y() < planted_height_ + options_.contact_height;
}

std::optional<Eigen::Vector3f> FootskateCleaner::ContactMean(int side, const Eigen::Vector3f& landing,
                                                             const AnkleLookahead& ahead, size_t from) const {
  Eigen::Vector3f sum = landing;
  int count = 1;
  const Eigen::Vector3f* previous = &landing;
  for (size_t k = from;; ++k) {
    const AnklePair* next = ahead.at(k);
    if (next == nullptr) {
      if (ahead.complete) break;  // the contact lasts to the segment's end
      return std::nullopt;        // the contact goes on beyond what is known
    }
    if (!EstimateSaysPlanted(*previous, (*next)[side])) break;
    previous = &(*next)[side];
    sum += *previous;
    ++count;
  }
  // A short contact is pinned where it began: eased in and out over a few frames each, a pin
  // moved to its mean is a bump in the leg's path.
  if (static_cast<float>(count) < options_.mean_pin_min_seconds * rate_) return std::nullopt;
  return sum / static_cast<float>(count);
}

Eigen::Vector3f FootskateCleaner::ApproachOffset(int side, const Eigen::Vector3f& estimate,
                                                 const AnkleLookahead& ahead) const {
  const Eigen::Vector3f* previous = &estimate;
  for (int k = 0; k < options_.release_frames; ++k) {
    const AnklePair* next = ahead.at(k);
    if (next == nullptr) break;
    const Eigen::Vector3f& landing = (*next)[side];
    if (EstimateSaysPlanted(*previous, landing)) {
      const auto mean = ContactMean(side, landing, ahead, k + 1);
      if (!mean) break;
      const float fraction =
          static_cast<float>(options_.release_frames - k) / static_cast<float>(options_.release_frames + 1);
      return fraction * (*mean - landing);
    }
    previous = &landing;
  }
  return Eigen::Vector3f::Zero();
}

std::array<bool, 2> FootskateCleaner::Process(const std::array<Eigen::Vector3f, 2>& estimated_ankles,
                                              const DatabaseFrame* source_frame, BodyPose* pose, AnkleTargets* targets,
                                              const AnkleLookahead& ahead) {
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
    if (use_estimate) estimated = foot.has_previous && EstimateSaysPlanted(foot.previous, estimate);
    contact[side] = database[side] && estimated;
    foot.previous = estimate;
    foot.has_previous = true;
    if (!options_.enabled) continue;
    body_.WorldTransforms(*pose, &rotations_, &positions_);
    const Eigen::Vector3f solved = positions_[ankle_joints[side]];
    if (contact[side]) {
      if (!foot.planted) {
        foot.pin = solved;  // the posed ankle, off the estimate by the solve's miss, which the pin keeps
        if (options_.pin_at_contact_mean && use_estimate) {
          if (const auto mean = ContactMean(side, estimate, ahead, 0)) foot.pin += *mean - estimate;
        }
      }
      foot.planted = true;
      foot.release_left = 0;
      SolveLegIk(body_, ankle_joints[side], foot.pin, pose);
      if (targets) (*targets)[side] = foot.pin;
      continue;
    }
    if (foot.planted) {
      foot.planted = false;
      foot.release_offset = foot.pin - solved;
      foot.release_left = options_.release_frames;
    }
    Eigen::Vector3f offset = Eigen::Vector3f::Zero();
    if (foot.release_left > 0) {
      const float fraction = static_cast<float>(foot.release_left) / static_cast<float>(options_.release_frames + 1);
      offset += fraction * foot.release_offset;
      --foot.release_left;
    }
    if (options_.pin_at_contact_mean && use_estimate) offset += ApproachOffset(side, estimate, ahead);
    if (!offset.isZero()) {
      const Eigen::Vector3f target = solved + offset;
      SolveLegIk(body_, ankle_joints[side], target, pose);
      if (targets) (*targets)[side] = target;
    }
  }
  return contact;
}

}  // namespace mocap

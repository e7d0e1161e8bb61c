#include "motion/reconstruct/reach_lean.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

namespace mocap {
namespace {

constexpr float kCollarSlack = 1e-3f;  // metres: see MoveCollars

// Turns `joint` by `world_turn` about itself, in world axes: its local rotation becomes the turned
// world rotation against its parent's (`world` holds the pose's world rotations).
void TurnInWorld(const Skeleton& skeleton, const std::vector<Eigen::Quaternionf>& world, int joint,
                 const Eigen::Quaternionf& world_turn, BodyPose* pose) {
  pose->rotations[joint] = (world[skeleton.parent(joint)].conjugate() * world_turn * world[joint]).normalized();
}

bool IsAncestor(const Skeleton& skeleton, int ancestor, int joint) {
  for (int j = joint; j >= 0; j = skeleton.parent(j)) {
    if (j == ancestor) return true;
  }
  return false;
}

}  // namespace

ReachLean::ReachLean(const Skeleton& skeleton, const BodyLandmarks& landmarks, const ReachLeanOptions& options)
    : options_(options) {
  const int wrists[2] = {landmarks.left_wrist, landmarks.right_wrist};
  for (int side = 0; side < 2; ++side) {
    const int wrist = wrists[side];
    const int elbow = wrist >= 0 ? skeleton.parent(wrist) : -1;
    const int shoulder = elbow >= 0 ? skeleton.parent(elbow) : -1;
    if (shoulder < 0) return;
    arms_[side] = {shoulder, elbow, wrist};  // the joints the arm IK turns (SolveLegIk)
  }
  // The chest: the nearest joint above both arms; the pivot: its ancestor just above the pelvis.
  int chest = arms_[0][0];
  while (chest >= 0 && !IsAncestor(skeleton, chest, arms_[1][0])) chest = skeleton.parent(chest);
  // A collar bone: the shoulder's parent when it is not the chest (rigs without one have none).
  for (int side = 0; side < 2; ++side) {
    const int collar = skeleton.parent(arms_[side][0]);
    if (collar >= 0 && chest >= 0 && collar != chest && IsAncestor(skeleton, chest, collar)) collars_[side] = collar;
  }
  const int pelvis = landmarks.pelvis;
  if (chest < 0 || pelvis < 0 || chest == pelvis || !IsAncestor(skeleton, pelvis, chest)) return;
  int pivot = chest;
  while (skeleton.parent(pivot) != pelvis) pivot = skeleton.parent(pivot);
  pivot_ = pivot;
}

bool ReachLean::ReadArms(const BodyModel& body, const BodyPose& pose, const std::array<Eigen::Vector3f, 2>& targets,
                         const std::array<bool, 2>& reach, std::array<Eigen::Vector3f, 2>* shoulder,
                         std::array<float, 2>* arm) {
  body.WorldTransforms(pose, &rotations_, &positions_);
  bool beyond = false;
  for (int side = 0; side < 2; ++side) {
    const auto [s, e, w] = arms_[side];
    (*shoulder)[side] = positions_[s];
    (*arm)[side] = (positions_[e] - positions_[s]).norm() + (positions_[w] - positions_[e]).norm();
    beyond = beyond || (reach[side] && (targets[side] - positions_[s]).norm() > (*arm)[side]);
  }
  return beyond;
}

float ReachLean::MoveCollars(const BodyModel& body, const std::array<Eigen::Vector3f, 2>& targets,
                             const std::array<bool, 2>& reach, BodyPose* pose) {
  if (!(options_.max_collar_angle > 0.0f) || (!reach[0] && !reach[1])) return 0.0f;
  std::array<Eigen::Vector3f, 2> shoulder;
  std::array<float, 2> arm{};
  if (!ReadArms(body, *pose, targets, reach, &shoulder, &arm)) return 0.0f;
  float largest = 0.0f;
  for (int side = 0; side < 2; ++side) {
    const int collar = collars_[side];
    if (!reach[side] || collar < 0 || (targets[side] - shoulder[side]).norm() <= arm[side]) continue;
    // Turning the collar by α towards the target (in the plane of u and v, which the arms do not
    // share, so one side's turn leaves the other's transforms as they were) leaves the shoulder
    // |t − s|² = |u|² + |v|² − 2|u||v|cos(β − α) from it: the least α that reaches, in closed form.
    const Eigen::Vector3f u = shoulder[side] - positions_[collar];
    const Eigen::Vector3f v = targets[side] - positions_[collar];
    const float lu = u.norm(), lv = v.norm();
    const Eigen::Vector3f axis = u.cross(v);
    if (!(lu > 0.0f) || !(lv > 0.0f) || !(axis.norm() > 1e-9f)) continue;
    const float beta = std::atan2(axis.norm(), u.dot(v));
    // A millimetre inside the arm, not on it: the lean and the shift after it count a hand
    // whose input is beyond reach, and one exactly on the edge would be counted or not by
    // rounding, which changed their solutions by millimetres (issue #12's equal conventions).
    const float reached = arm[side] - kCollarSlack;
    const float reaching_cosine = (lu * lu + lv * lv - reached * reached) / (2.0f * lu * lv);
    const float needed = reaching_cosine >= 1.0f ? beta : beta - std::acos(std::max(-1.0f, reaching_cosine));
    const float alpha = std::clamp(needed, 0.0f, std::min(beta, options_.max_collar_angle));
    if (!(alpha > 0.0f)) continue;
    TurnInWorld(body.skeleton(), rotations_, collar, Eigen::Quaternionf(Eigen::AngleAxisf(alpha, axis.normalized())),
                pose);
    largest = std::max(largest, alpha);
  }
  return largest;
}

float ReachLean::Apply(const BodyModel& body, const std::array<Eigen::Vector3f, 2>& targets,
                       const std::array<bool, 2>& reach, BodyPose* pose) {
  const Eigen::Vector3f omega = LeastTurn(body, targets, reach, *pose);
  Turn(body, omega, pose);
  return omega.norm();
}

float ReachLean::Apply(const BodyModel& body, const std::array<Eigen::Vector3f, 2>& targets,
                       const std::array<bool, 2>& reach, double frame_time, Eigen::Vector3f* state, BodyPose* pose) {
  const Eigen::Vector3f omega = LeastTurn(body, targets, reach, *pose);
  const float dt = static_cast<float>(frame_time);
  const float follow = options_.turn_smoothing_seconds > 0 ? dt / (options_.turn_smoothing_seconds + dt) : 1.0f;
  *state += follow * (omega - *state);
  Turn(body, *state, pose);
  return state->norm();
}

void ReachLean::Turn(const BodyModel& body, const Eigen::Vector3f& omega, BodyPose* pose) {
  const float angle = omega.norm();
  if (pivot_ < 0 || !(angle > 0.0f)) return;
  body.WorldTransforms(*pose, &rotations_, &positions_);
  TurnInWorld(body.skeleton(), rotations_, pivot_, Eigen::Quaternionf(Eigen::AngleAxisf(angle, omega / angle)), pose);
}

Eigen::Vector3f ReachLean::LeastTurn(const BodyModel& body, const std::array<Eigen::Vector3f, 2>& targets,
                                     const std::array<bool, 2>& reach, const BodyPose& pose) {
  if (pivot_ < 0 || !(options_.max_angle > 0.0f) || (!reach[0] && !reach[1])) return Eigen::Vector3f::Zero();
  // A relaxed arm hangs straight, so the lean starts only where the input is beyond the arm's
  // length (a lean that began a few centimetres before it bent the lab's standing bodies all the
  // time: standard split 2.18 → 2.64 cm).
  std::array<Eigen::Vector3f, 2> shoulder;
  std::array<float, 2> arm{};
  if (!ReadArms(body, pose, targets, reach, &shoulder, &arm)) return Eigen::Vector3f::Zero();
  const Eigen::Vector3f pivot = positions_[pivot_];
  for (Eigen::Vector3f& a : shoulder) a -= pivot;  // relative to the pivot
  // Gauss-Newton on the turn ω (world, at the pivot): residual per reaching hand, its shoulder's
  // distance to the input past the arm's length; a small damping keeps the turn the least that
  // reaches.
  Eigen::Vector3f omega = Eigen::Vector3f::Zero();
  for (int iteration = 0; iteration < 4; ++iteration) {
    const Eigen::AngleAxisf turn(omega.norm(), omega.norm() > 0 ? omega.normalized() : Eigen::Vector3f::UnitX());
    Eigen::Matrix3f normal = 1e-4f * Eigen::Matrix3f::Identity();
    Eigen::Vector3f gradient = Eigen::Vector3f::Zero();
    bool any = false;
    for (int side = 0; side < 2; ++side) {
      if (!reach[side]) continue;
      const Eigen::Vector3f a = turn * shoulder[side];
      const Eigen::Vector3f to_target = targets[side] - pivot - a;
      const float distance = to_target.norm();
      const float residual = distance - arm[side];
      if (residual <= 0.0f || distance <= 0.0f) continue;
      // d(residual)/dδ for a further turn δ: the shoulder moves by δ × a.
      const Eigen::Vector3f jacobian = -a.cross(to_target / distance);
      normal += jacobian * jacobian.transpose();
      gradient += jacobian * residual;
      any = true;
    }
    if (!any) break;
    const Eigen::Vector3f step = -normal.ldlt().solve(gradient);
    const Eigen::AngleAxisf composed(
        Eigen::AngleAxisf(step.norm(), step.norm() > 0 ? step.normalized() : Eigen::Vector3f::UnitX()) * turn);
    omega = composed.angle() * composed.axis();
    if (omega.norm() > options_.max_angle) omega *= options_.max_angle / omega.norm();
  }
  return omega;
}

Eigen::Vector3f ReachLean::Shift(const BodyModel& body, const std::array<Eigen::Vector3f, 2>& targets,
                                 const std::array<bool, 2>& reach, double frame_time, Eigen::Vector3f* state,
                                 BodyPose* pose, const BodyMotion* moving) {
  const float dt = static_cast<float>(frame_time);
  Eigen::Vector3f wanted = WantedShift(body, targets, reach, *pose);
  // Down towards input on the floor no further than the body can go: the joints it rests on stay
  // above the ground, as in A6's solve (E_floor). A shift made frames ago gives way where the body
  // the solve gives now is lower, no faster than floor_give_way_speed.
  float lowest = 0.0f;  // the lowest shift the floor allows (≤ 0)
  const bool down = options_.vertical_shift && (wanted.y() < 0.0f || state->y() < 0.0f);
  if (down) {
    body.WorldTransforms(*pose, &rotations_, &positions_);
    lowest = std::min(0.0f, -body.FloorClearance(positions_));
    wanted.y() = std::max(wanted.y(), lowest);
  }
  const float step = options_.max_shift_speed * dt;
  Eigen::Vector3f change = wanted - *state;
  if (change.norm() > step) change *= step / change.norm();
  if (moving != nullptr) change *= PartWithinLimit(moving->velocity * dt, change, moving->speed_bound * dt);
  *state += change;
  if (down && state->y() < lowest) state->y() = std::min(lowest, state->y() + options_.floor_give_way_speed * dt);
  pose->root_position += *state;
  return *state;
}

float PartWithinLimit(const Eigen::Vector3f& step, const Eigen::Vector3f& change, float limit) {
  const float change_squared = change.squaredNorm();
  if (!(change_squared > 0.0f) || !std::isfinite(limit)) return 1.0f;
  // |step + α change|² ≤ R² for α up to the larger root of α²|c|² + 2α s·c + |s|² − R² (R ≥ |s|,
  // so the roots bracket 0).
  const float radius_squared = std::max(limit * limit, step.squaredNorm());
  const float along = step.dot(change);
  const float root =
      (-along + std::sqrt(std::max(0.0f, along * along - change_squared * (step.squaredNorm() - radius_squared)))) /
      change_squared;
  return std::clamp(root, 0.0f, 1.0f);
}

Eigen::Vector3f ReachLean::WantedShift(const BodyModel& body, const std::array<Eigen::Vector3f, 2>& targets,
                                       const std::array<bool, 2>& reach, const BodyPose& pose) {
  if (pivot_ < 0 || !(options_.max_shift > 0.0f) || (!reach[0] && !reach[1])) return Eigen::Vector3f::Zero();
  std::array<Eigen::Vector3f, 2> shoulder;
  std::array<float, 2> arm{};
  if (!ReadArms(body, pose, targets, reach, &shoulder, &arm)) return Eigen::Vector3f::Zero();
  const Eigen::Vector3f axes = options_.vertical_shift ? Eigen::Vector3f::Ones() : Eigen::Vector3f(1.0f, 0.0f, 1.0f);
  Eigen::Vector3f shift = Eigen::Vector3f::Zero();
  for (int iteration = 0; iteration < 4; ++iteration) {
    Eigen::Matrix3f normal = 1e-4f * Eigen::Matrix3f::Identity();
    Eigen::Vector3f gradient = Eigen::Vector3f::Zero();
    bool any = false;
    for (int side = 0; side < 2; ++side) {
      if (!reach[side]) continue;
      const Eigen::Vector3f to_target = targets[side] - shoulder[side] - shift;
      const float distance = to_target.norm();
      const float residual = distance - arm[side];
      if (residual <= 0.0f || distance <= 0.0f) continue;
      const Eigen::Vector3f jacobian = -(to_target / distance).cwiseProduct(axes);
      normal += jacobian * jacobian.transpose();
      gradient += jacobian * residual;
      any = true;
    }
    if (!any) break;
    shift += (-normal.ldlt().solve(gradient)).cwiseProduct(axes);
    if (shift.norm() > options_.max_shift) shift *= options_.max_shift / shift.norm();
  }
  return shift;
}

}  // namespace mocap

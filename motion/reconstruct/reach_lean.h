// A body reaches further by leaning (issue #22: hands that miss their own input). After the
// motion guard has placed the body, a hand whose input lies beyond the arm's reach from its
// shoulder cannot get there by arm IK alone: the arm stretches straight and misses by the rest.
// Where the input is beyond reach the collar bones first turn the shoulders towards it
// (`MoveCollars`, a few centimetres), then the torso turns at the lowest spine joint, as far as
// `max_angle`, so that the shoulders come within reach; where that is not enough the whole body
// moves towards the input (`Shift`, bounded in distance and speed); the arm IK then puts the
// hands on the input. A person whose hands are there has shoulders within an arm of them, so the turn moves the
// shoulders (and head) towards where they must have been; wrists within reach change nothing.
#pragma once

#include <array>
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "motion/reconstruct/body_model.h"
#include "motion/skeleton/body_topology.h"

namespace mocap {

struct ReachLeanOptions {
  // Before the torso leans, each collar bone (the joint between the chest and the arm) turns its
  // shoulder towards input beyond reach, by at most this angle, radians (0 = off): a person drops,
  // raises or pushes forward the shoulder before bending the trunk. The shoulder girdle's own
  // range is tens of degrees (elevation ~40°, depression and protraction 10–20°); 0.25 rad ≈ 14°
  // moves a 15 cm collar bone's shoulder by ~4 cm, the few centimetres an arm longer than the
  // database's misses by (a longer-armed walker's hanging hands made a 0.5 rad lean: the torso
  // turned towards a hand below the shoulder, where a turn barely reaches).
  float max_collar_angle = 0.25f;
  // The farthest the torso turns, radians (0 = off). A standing person reaching for something
  // leans and twists the trunk by tens of degrees; 0.5 rad ≈ 29°.
  float max_angle = 0.5f;
  // Where the turn is not enough, the whole body moves towards the input (a step, a crouch, a
  // rise on the toes), at most this far, metres (0 = off): the body was solved from neighbours
  // whose hands were nearer, and a person whose hands are there has shoulders within an arm of them.
  float max_shift = 0.3f;
  // Up and down as well as over the ground. Over the ground only, a low input pulled the body
  // sideways: cross-dataset 15.87 → 16.12 cm, against 15.69 with the vertical (issue #22).
  bool vertical_shift = true;
  // How fast the shift follows (m/s): a body shifting its weight or bending its knees to reach, not
  // a jump. 0.25 m/s kept the clips over the allowed pelvis speed at 7 of 227 (cross-dataset);
  // 0.5 m/s made them 11 (wrists 1.07 → 1.00 cm), unbounded 41.
  float max_shift_speed = 0.25f;
  // How fast a shift down gives way where the body under it comes lower than its floor joints
  // allow the shift to take it (m/s; docs/method.md A7): faster than the shift itself, so a body
  // going down to the floor is not pushed into it for long, and no jump.
  float floor_give_way_speed = 2.0f;
  // The streamed turn (the Apply with a state) follows the least turn through an exponential
  // filter of this time constant, seconds (0 = at once): the least turn moves with the input's
  // noise, and the torso above the pivot magnifies it (a shoulder 0.4 m from the pivot, the head
  // 0.6 m), which made the head's jerk 10 × the capture's on 60 Hz input with 5 mm of jitter.
  float turn_smoothing_seconds = 0.1f;
};

// How the body under a shift moves (ReachLean::Shift): its pelvis's velocity this frame and the
// fastest the pelvis may go, m/s (infinite: no bound, as on a stream's first frame).
struct BodyMotion {
  Eigen::Vector3f velocity = Eigen::Vector3f::Zero();
  float speed_bound = std::numeric_limits<float>::infinity();
};

// The largest part α ∈ [0, 1] of `change` such that |`step` + α·`change`| ≤ max(`limit`, |`step`|):
// a change on top of a step no longer than the limit allows (nor longer than the step already is).
float PartWithinLimit(const Eigen::Vector3f& step, const Eigen::Vector3f& change, float limit);

class ReachLean {
 public:
  // No spine between the pelvis and the shoulders (or no shoulders): the lean does nothing.
  ReachLean(const Skeleton& skeleton, const BodyLandmarks& landmarks, const ReachLeanOptions& options = {});

  // Turns each collar bone of a hand with `reach[side]` set so its shoulder comes within an arm of
  // `targets[side]`, at most `max_collar_angle` (the least turn, towards the target). Returns the
  // larger angle turned (radians). Runs before the lean.
  float MoveCollars(const BodyModel& body, const std::array<Eigen::Vector3f, 2>& targets,
                    const std::array<bool, 2>& reach, BodyPose* pose);
  // Turns `pose`'s torso so the shoulders of the hands with `reach[side]` set come within an arm of
  // `targets[side]`. Returns the angle turned (radians).
  float Apply(const BodyModel& body, const std::array<Eigen::Vector3f, 2>& targets, const std::array<bool, 2>& reach,
              BodyPose* pose);
  // The same for consecutive frames `frame_time` apart: `*state` is the turn of the frame before
  // (a rotation vector, world), and the turn made follows the least one through
  // `turn_smoothing_seconds`. Returns the angle turned.
  float Apply(const BodyModel& body, const std::array<Eigen::Vector3f, 2>& targets, const std::array<bool, 2>& reach,
              double frame_time, Eigen::Vector3f* state, BodyPose* pose);
  // After `Apply`: the least shift of the whole body, at most `max_shift`, that brings the
  // shoulders of the reaching hands within an arm of their targets. `*state` is the shift of the
  // frame before (`frame_time` earlier); it moves towards the new one no faster than
  // `max_shift_speed`. Downwards it goes no further than the body's floor joints allow
  // (BodyModel::FloorClearance). Moves `pose`'s root by it and returns it.
  // `moving`: how the body under the shift moves this frame (the motion guard's pelvis): the
  // shift's change is cut so that the two together stay within its speed bound (a braking body's
  // own speed, if that is more). Without it the shift's `max_shift_speed` came on top of a guard
  // at its bound: a guiding gesture 1.25 × over the allowed pelvis speed at lag 0 (issue #22). A
  // shift down that gives way to the floor is not cut.
  Eigen::Vector3f Shift(const BodyModel& body, const std::array<Eigen::Vector3f, 2>& targets,
                        const std::array<bool, 2>& reach, double frame_time, Eigen::Vector3f* state, BodyPose* pose,
                        const BodyMotion* moving = nullptr);

  int pivot() const { return pivot_; }

 private:
  // The pose's world transforms into the scratch, each arm's shoulder (world) and straight length;
  // true when a reaching hand's target is beyond its arm.
  bool ReadArms(const BodyModel& body, const BodyPose& pose, const std::array<Eigen::Vector3f, 2>& targets,
                const std::array<bool, 2>& reach, std::array<Eigen::Vector3f, 2>* shoulder, std::array<float, 2>* arm);
  // The least turn ω (a rotation vector, world, at the pivot) that brings the reaching hands'
  // shoulders within an arm of their targets, at most max_angle; zero when none is needed.
  Eigen::Vector3f LeastTurn(const BodyModel& body, const std::array<Eigen::Vector3f, 2>& targets,
                            const std::array<bool, 2>& reach, const BodyPose& pose);
  void Turn(const BodyModel& body, const Eigen::Vector3f& omega, BodyPose* pose);
  Eigen::Vector3f WantedShift(const BodyModel& body, const std::array<Eigen::Vector3f, 2>& targets,
                              const std::array<bool, 2>& reach, const BodyPose& pose);
  ReachLeanOptions options_;
  int pivot_ = -1;                             // the lowest spine joint: the pelvis' child towards the shoulders
  std::array<std::array<int, 3>, 2> arms_{};   // shoulder, elbow, wrist per side
  std::array<int, 2> collars_{-1, -1};         // the shoulder's parent below the chest, or −1
  std::vector<Eigen::Quaternionf> rotations_;  // scratch
  std::vector<Eigen::Vector3f> positions_;
};

}  // namespace mocap

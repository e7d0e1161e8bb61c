// A body reaches further by leaning (issue #22: hands that miss their own input). After the
// motion guard has placed the body, a hand whose input lies beyond the arm's reach from its
// shoulder cannot get there by arm IK alone: the arm stretches straight and misses by the rest.
// Where the input is beyond reach the torso turns at the lowest spine joint, as far as
// `max_angle`, so that the shoulders come within reach; the arm IK then puts the hands on the
// input. A person whose hands are there has shoulders within an arm of them, so the turn moves the
// shoulders (and head) towards where they must have been; wrists within reach change nothing.
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "motion/reconstruct/body_model.h"
#include "motion/skeleton/body_topology.h"

namespace mocap {

struct ReachLeanOptions {
  // The farthest the torso turns, radians (0 = off). A standing person reaching for something
  // leans and twists the trunk by tens of degrees; 0.5 rad ≈ 29°.
  float max_angle = 0.5f;
};

class ReachLean {
 public:
  // No spine between the pelvis and the shoulders (or no shoulders): the lean does nothing.
  ReachLean(const Skeleton& skeleton, const BodyLandmarks& landmarks, const ReachLeanOptions& options = {});

  // Turns `pose`'s torso so the shoulders of the hands with `reach[side]` set come within an arm of
  // `targets[side]`. Returns the angle turned (radians).
  float Apply(const BodyModel& body, const std::array<Eigen::Vector3f, 2>& targets, const std::array<bool, 2>& reach,
              BodyPose* pose);

  int pivot() const { return pivot_; }

 private:
  ReachLeanOptions options_;
  int pivot_ = -1;                             // the lowest spine joint: the pelvis' child towards the shoulders
  std::array<std::array<int, 3>, 2> arms_{};   // shoulder, elbow, wrist per side
  std::vector<Eigen::Quaternionf> rotations_;  // scratch
  std::vector<Eigen::Vector3f> positions_;
};

}  // namespace mocap

// Footskate cleanup of METHOD.md A7 (in the manner of Kovar, Schreiner & Gleicher 2002), causal so
// that the stream and the offline path share it: a foot is planted while its estimated ankle moves
// slower than `contact_speed` on the ground plane and sits lower than `contact_height` above the
// database's planted ankle height. While planted the ankle is pinned where the contact began and
// the leg is solved by two-bone inverse kinematics (hip and knee turn; the foot keeps its world
// orientation). When the contact ends the correction fades out over `release_frames` frames.
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "motion/reconstruct/body_model.h"

namespace mocap {

struct FootskateOptions {
  bool enabled = true;
  float contact_speed = 0.30f;   // m/s, ground-plane ankle speed
  float contact_height = 0.06f;  // m above the planted ankle height
  int release_frames = 4;
};

// Moves `pose` so that the ankle (the leg's end joint) reaches `target`: analytic two-bone IK on
// the ankle's parent (knee) and grandparent (hip). Out-of-reach targets stretch the leg straight
// towards them.
void SolveLegIk(const BodyModel& body, int ankle_joint, const Eigen::Vector3f& target, BodyPose* pose);

class FootskateCleaner {
 public:
  FootskateCleaner(const BodyModel& body, float planted_ankle_height, double frame_time, const FootskateOptions& options);

  // Next frame: `estimated_ankles` are the A4 ankle controls. Adjusts `pose`; returns the
  // contact flags [left, right].
  std::array<bool, 2> Process(const std::array<Eigen::Vector3f, 2>& estimated_ankles, BodyPose* pose);
  void Reset();

 private:
  struct Foot {
    bool planted = false;
    Eigen::Vector3f pin = Eigen::Vector3f::Zero();
    Eigen::Vector3f release_offset = Eigen::Vector3f::Zero();
    int release_left = 0;
    bool has_previous = false;
    Eigen::Vector3f previous = Eigen::Vector3f::Zero();
  };
  const BodyModel& body_;
  float planted_height_;
  float rate_;
  FootskateOptions options_;
  std::array<Foot, 2> feet_;
  std::vector<Eigen::Quaternionf> rotations_;
  std::vector<Eigen::Vector3f> positions_;
};

}  // namespace mocap

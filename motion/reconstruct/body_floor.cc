#include "motion/reconstruct/body_floor.h"

#include <algorithm>

namespace mocap {

std::vector<int> FloorBearingJoints(const Skeleton& skeleton, const BodyLandmarks& landmarks) {
  const int n = skeleton.num_joints();
  std::vector<bool> excluded(n, false);
  if (landmarks.pelvis >= 0) {
    for (int j = skeleton.parent(landmarks.pelvis); j >= 0; j = skeleton.parent(j)) excluded[j] = true;
  }
  const int ends[] = {landmarks.left_ankle, landmarks.right_ankle, landmarks.left_wrist, landmarks.right_wrist};
  // Parents come before children in a skeleton's order: one pass marks every joint past an end.
  std::vector<bool> past_end(n, false);
  for (int j = 0; j < n; ++j) {
    const int parent = skeleton.parent(j);
    if (parent >= 0 && (past_end[parent] || std::find(std::begin(ends), std::end(ends), parent) != std::end(ends)))
      past_end[j] = true;
  }
  std::vector<int> joints;
  for (int j = 0; j < n; ++j) {
    const bool ankle = j == landmarks.left_ankle || j == landmarks.right_ankle;
    if (!excluded[j] && !past_end[j] && !ankle) joints.push_back(j);
  }
  return joints;
}

float FloorLift(std::span<const Eigen::Vector3f> world_positions, std::span<const int> joints) {
  float lowest = 0.0f;
  for (const int j : joints) lowest = std::min(lowest, world_positions[j].y());
  return -lowest;
}

}  // namespace mocap

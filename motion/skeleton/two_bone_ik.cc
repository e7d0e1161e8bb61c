#include "motion/skeleton/two_bone_ik.h"

#include <algorithm>
#include <cmath>

namespace mocap {

TwoBoneTurns SolveTwoBoneIk(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c,
                            const Eigen::Vector3f& target, const Eigen::Vector3f& bend_axis) {
  TwoBoneTurns turns;
  const float upper = (b - a).norm(), lower = (c - b).norm();
  if (upper < 1e-5f || lower < 1e-5f) return turns;
  const float reach = std::clamp((target - a).norm(), std::abs(upper - lower) + 1e-4f, upper + lower - 1e-4f);
  // Middle joint: change the interior angle so that the a-to-c distance equals the reach.
  const Eigen::Vector3f to_root = (a - b) / upper, to_end = (c - b) / lower;
  const float current = std::acos(std::clamp(to_root.dot(to_end), -1.0f, 1.0f));
  const float wanted =
      std::acos(std::clamp((upper * upper + lower * lower - reach * reach) / (2 * upper * lower), -1.0f, 1.0f));
  Eigen::Vector3f axis = to_root.cross(to_end);
  if (axis.norm() < 1e-6f) axis = bend_axis;  // straight chain: the caller's bend plane
  if (axis.norm() < 1e-9f) return turns;
  axis.normalize();
  turns.middle_turn = Eigen::Quaternionf(Eigen::AngleAxisf(wanted - current, axis));
  const Eigen::Vector3f bent_end = b + turns.middle_turn * (c - b);
  // Root joint: swing the chain so that its end lies on the line to the target.
  turns.root_turn = Eigen::Quaternionf::FromTwoVectors(bent_end - a, target - a);
  return turns;
}

}  // namespace mocap

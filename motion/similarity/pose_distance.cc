#include "motion/similarity/pose_distance.h"

#include <cmath>

namespace mocap {

PoseDistance ComparePoses(const float* query, const float* candidate, int num_points, int points_per_group,
                          const GroupWeights& weights) {
  const int pose_points = kNumBodyGroups * points_per_group;
  // Weighted centroids on the ground plane.
  double w_sum = 0, qx = 0, qz = 0, cx = 0, cz = 0;
  for (int i = 0; i < num_points; ++i) {
    const float w = weights.weight[(i % pose_points) / points_per_group];
    w_sum += w;
    qx += w * query[3 * i];
    qz += w * query[3 * i + 2];
    cx += w * candidate[3 * i];
    cz += w * candidate[3 * i + 2];
  }
  PoseDistance result;
  if (w_sum <= 0) return result;
  qx /= w_sum;
  qz /= w_sum;
  cx /= w_sum;
  cz /= w_sum;
  // Closed form (Kovar et al. 2002): the yaw maximising sum w q·R(c) about the centroids.
  double a = 0, b = 0;
  for (int i = 0; i < num_points; ++i) {
    const float w = weights.weight[(i % pose_points) / points_per_group];
    const double px = query[3 * i] - qx, pz = query[3 * i + 2] - qz;
    const double ux = candidate[3 * i] - cx, uz = candidate[3 * i + 2] - cz;
    a += w * (px * ux + pz * uz);
    b += w * (px * uz - pz * ux);
  }
  const double yaw = std::atan2(b, a);
  const float c = static_cast<float>(std::cos(yaw)), s = static_cast<float>(std::sin(yaw));
  // R_y(yaw) maps (x, z) to (x c + z s, -x s + z c); the translation maps centroid onto centroid.
  const float tx = static_cast<float>(qx - (cx * c + cz * s));
  const float tz = static_cast<float>(qz - (-cx * s + cz * c));
  result.alignment = {static_cast<float>(yaw), tx, tz};
  for (int i = 0; i < num_points; ++i) {
    const float x = candidate[3 * i], y = candidate[3 * i + 1], z = candidate[3 * i + 2];
    const float dx = query[3 * i] - (x * c + z * s + tx);
    const float dy = query[3 * i + 1] - y;
    const float dz = query[3 * i + 2] - (-x * s + z * c + tz);
    result.per_group[(i % pose_points) / points_per_group] += std::sqrt(dx * dx + dy * dy + dz * dz);
  }
  for (int g = 0; g < kNumBodyGroups; ++g) result.total += weights.weight[g] * result.per_group[g];
  return result;
}

}  // namespace mocap

// Angles for tests: π, a degree, and the angle between two rotations.
#pragma once

#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

namespace mocap::testing {

inline constexpr float kPi = std::numbers::pi_v<float>;
inline constexpr float kDegree = kPi / 180.0f;

// Angle in radians of the rotation taking `a` to `b` (q and -q are the same rotation).
inline double AngleBetween(const Eigen::Quaternionf& a, const Eigen::Quaternionf& b) {
  const Eigen::Quaterniond d = a.cast<double>().normalized().conjugate() * b.cast<double>().normalized();
  return 2 * std::atan2(d.vec().norm(), std::abs(d.w()));
}

}  // namespace mocap::testing

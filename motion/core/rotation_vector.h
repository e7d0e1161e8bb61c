// Rotation vectors (exp map): axis × angle in radians, the compact rotation encoding of poses.
#pragma once

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace mocap {

// Shortest-arc rotation vector of a quaternion (angle in [0, π]).
template <typename T>
Eigen::Matrix<T, 3, 1> RotationVector(const Eigen::Quaternion<T>& q_in) {
  Eigen::Quaternion<T> q = q_in.normalized();
  if (q.w() < 0) q.coeffs() *= T(-1);
  const Eigen::Matrix<T, 3, 1> v = q.vec();
  const T s = v.norm();
  if (s < T(1e-7)) return T(2) * v;
  return v * (T(2) * std::atan2(s, q.w()) / s);
}

template <typename Derived>
Eigen::Quaternion<typename Derived::Scalar> FromRotationVector(const Eigen::MatrixBase<Derived>& v) {
  using T = typename Derived::Scalar;
  const T angle = v.norm();
  if (angle < T(1e-7)) return Eigen::Quaternion<T>(T(1), T(0.5) * v.x(), T(0.5) * v.y(), T(0.5) * v.z()).normalized();
  return Eigen::Quaternion<T>(Eigen::AngleAxis<T>(angle, v / angle));
}

}  // namespace mocap

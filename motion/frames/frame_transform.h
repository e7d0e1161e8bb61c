// Points, vectors and rotations between a caller's frame (FrameConvention plus a floor height)
// and the native frame (metres, right-handed, Y up, floor at y = 0).
//
// With C = NativeBasis(...) (a signed permutation, det ±1), s = metres per caller unit and f the
// native height of the caller's floor:
//   position   p' = s·C·p − (0, f, 0)          (and back: p = Cᵀ(p' + (0, f, 0)) / s)
//   offset     v' = s·C·v                       (skeleton offsets, displacements: no floor)
//   rotation   R' = C·R·C⁻¹                     (a proper rotation again, also when det C = −1)
// A pose given by local rotations and offsets therefore maps joint by joint: forward kinematics
// in the caller's frame of the converted pose equals the converted native forward kinematics.
//
// Thread safety: immutable after construction.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "motion/frames/frame_convention.h"

namespace mocap {

class FrameTransform {
 public:
  FrameTransform() = default;  // the native frame itself
  // `floor_height`: the floor's coordinate on the caller's up axis (the axis as written: for
  // up = −Y a floor 0.9 below the origin is y = +0.9), caller units.
  FrameTransform(const FrameConvention& convention, double floor_height);

  Eigen::Vector3f PositionToNative(const Eigen::Vector3f& p) const { return metres_per_unit_ * (basis_ * p) - floor_; }
  Eigen::Vector3f PositionFromNative(const Eigen::Vector3f& p) const {
    return basis_.transpose() * (p + floor_) / metres_per_unit_;
  }
  Eigen::Vector3f VectorToNative(const Eigen::Vector3f& v) const { return metres_per_unit_ * (basis_ * v); }
  Eigen::Vector3f VectorFromNative(const Eigen::Vector3f& v) const { return basis_.transpose() * v / metres_per_unit_; }
  // C·R·C⁻¹ on the quaternion, exactly: the axis becomes det(C)·C·axis, the angle stays.
  Eigen::Quaternionf RotationToNative(const Eigen::Quaternionf& q) const { return Conjugate(basis_, q); }
  Eigen::Quaternionf RotationFromNative(const Eigen::Quaternionf& q) const { return Conjugate(basis_.transpose(), q); }
  float LengthToNative(float length) const { return length * metres_per_unit_; }
  float LengthFromNative(float metres) const { return metres / metres_per_unit_; }

  const Eigen::Matrix3f& basis() const { return basis_; }
  float metres_per_unit() const { return metres_per_unit_; }
  // Native height (metres) of the caller's floor: what PositionToNative subtracts from y.
  float floor_native() const { return floor_.y(); }

 private:
  Eigen::Quaternionf Conjugate(const Eigen::Matrix3f& c, const Eigen::Quaternionf& q) const {
    const Eigen::Vector3f axis = determinant_ * (c * q.vec());
    return Eigen::Quaternionf(q.w(), axis.x(), axis.y(), axis.z());
  }

  Eigen::Matrix3f basis_ = Eigen::Matrix3f::Identity();
  float determinant_ = 1.0f;
  float metres_per_unit_ = 1.0f;
  Eigen::Vector3f floor_ = Eigen::Vector3f::Zero();  // (0, f, 0)
};

// The floor coordinate (caller units, on the caller's up axis) whose native height is
// `native_height` metres: the inverse of the constructor's rule (a calibrated floor, reported
// back to the caller).
double FloorHeightFromNative(const FrameConvention& convention, float native_height);

}  // namespace mocap

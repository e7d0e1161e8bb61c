#include "motion/frames/frame_transform.h"

#include <Eigen/LU>

namespace mocap {

FrameTransform::FrameTransform(const FrameConvention& convention, double floor_height)
    : basis_(NativeBasis(convention.up, convention.handedness)),
      determinant_(basis_.determinant() < 0 ? -1.0f : 1.0f),
      metres_per_unit_(static_cast<float>(MetresPerUnit(convention.unit))) {
  floor_.y() = static_cast<float>(floor_height * MetresPerUnit(convention.unit)) * UpAxisSign(convention.up);
}

double FloorHeightFromNative(const FrameConvention& convention, float native_height) {
  return native_height / MetresPerUnit(convention.unit) * UpAxisSign(convention.up);
}

}  // namespace mocap

#include "server/input_frame_convert.h"


namespace mocap {
namespace {

Eigen::Vector3f FromProto(const v1::Vec3& v) { return {v.x(), v.y(), v.z()}; }
void ToProto(const Eigen::Vector3f& v, v1::Vec3* out) {
  out->set_x(v.x());
  out->set_y(v.y());
  out->set_z(v.z());
}

void PositionToCaller(const FrameTransform& transform, v1::Vec3* v) {
  ToProto(transform.PositionFromNative(FromProto(*v)), v);
}
void VectorToCaller(const FrameTransform& transform, v1::Vec3* v) { ToProto(transform.VectorFromNative(FromProto(*v)), v); }
void RotationToCaller(const FrameTransform& transform, v1::Quaternion* q) {
  const Eigen::Quaternionf r = transform.RotationFromNative(Eigen::Quaternionf(q->w(), q->x(), q->y(), q->z()));
  q->set_w(r.w());
  q->set_x(r.x());
  q->set_y(r.y());
  q->set_z(r.z());
}


}  // namespace

(v1::INPUT_WARNING_KIND_UNITS); break;
    case InputWarning::Kind::kBelowFloor: out.set_kind(v1::INPUT_WARNING_KIND_BELOW_FLOOR); break;
    case InputWarning::Kind::kAboveFloor: out.set_kind(v1::INPUT_WARNING_KIND_ABOVE_FLOOR); break;
    case InputWarning::Kind::kSwapped: out.set_kind(v1::INPUT_WARNING_KIND_SWAPPED); break;
  }
  out.set_message(warning.message);
  return out;
}

}  // namespace mocap

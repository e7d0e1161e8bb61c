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
void VectorToCaller(const FrameTransform& transform, v1::Vec3* v) {
  ToProto(transform.VectorFromNative(FromProto(*v)), v);
}
void RotationToCaller(const FrameTransform& transform, v1::Quaternion* q) {
  const Eigen::Quaternionf r = transform.RotationFromNative(Eigen::Quaternionf(q->w(), q->x(), q->y(), q->z()));
  q->set_w(r.w());
  q->set_x(r.x());
  q->set_y(r.y());
  q->set_z(r.z());
}

}  // namespace

void ToCallerFrame(const FrameTransform& transform, v1::Skeleton* skeleton) {
  for (v1::Joint& joint : *skeleton->mutable_joints()) {
    VectorToCaller(transform, joint.mutable_offset());
    if (joint.has_end_site()) VectorToCaller(transform, joint.mutable_end_site());
  }
}

void ToCallerFrame(const FrameTransform& transform, v1::Frame* frame) {
  PositionToCaller(transform, frame->mutable_root_position());
  for (v1::Quaternion& q : *frame->mutable_rotations()) RotationToCaller(transform, &q);
  PositionToCaller(transform, frame->mutable_pelvis_position());
  RotationToCaller(transform, frame->mutable_pelvis_rotation());
  for (v1::Vec3* v : {frame->mutable_left_ankle(), frame->mutable_right_ankle(), frame->mutable_left_wrist(),
                      frame->mutable_right_wrist()}) {
    PositionToCaller(transform, v);
  }
  if (frame->has_expected_error()) {  // lengths: every field, whatever the landmarks are
    const google::protobuf::Descriptor* descriptor = v1::LandmarkErrors::descriptor();
    const google::protobuf::Reflection* reflection = v1::LandmarkErrors::GetReflection();
    v1::LandmarkErrors* errors = frame->mutable_expected_error();
    for (int k = 0; k < descriptor->field_count(); ++k) {
      const google::protobuf::FieldDescriptor* field = descriptor->field(k);
      reflection->SetFloat(errors, field, transform.LengthFromNative(reflection->GetFloat(*errors, field)));
    }
  }
  if (!frame->has_diagnostics()) return;
  v1::FrameDiagnostics* d = frame->mutable_diagnostics();
  d->set_left_wrist_error(transform.LengthFromNative(d->left_wrist_error()));
  d->set_right_wrist_error(transform.LengthFromNative(d->right_wrist_error()));
  d->set_left_ankle_error(transform.LengthFromNative(d->left_ankle_error()));
  d->set_right_ankle_error(transform.LengthFromNative(d->right_ankle_error()));
}

v1::InputWarning ToProto(const InputWarning& warning) {
  v1::InputWarning out;
  switch (warning.kind) {
    case InputWarning::Kind::kUnits:
      out.set_kind(v1::INPUT_WARNING_KIND_UNITS);
      break;
    case InputWarning::Kind::kBelowFloor:
      out.set_kind(v1::INPUT_WARNING_KIND_BELOW_FLOOR);
      break;
    case InputWarning::Kind::kAboveFloor:
      out.set_kind(v1::INPUT_WARNING_KIND_ABOVE_FLOOR);
      break;
    case InputWarning::Kind::kSwapped:
      out.set_kind(v1::INPUT_WARNING_KIND_SWAPPED);
      break;
    case InputWarning::Kind::kUpAxis:
      out.set_kind(v1::INPUT_WARNING_KIND_UP_AXIS);
      break;
  }
  out.set_message(warning.message);
  return out;
}

}  // namespace mocap

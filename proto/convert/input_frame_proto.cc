#include "proto/convert/input_frame_proto.h"

#include <algorithm>
#include <cctype>
#include <string>

#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"

namespace mocap {
namespace {

constexpr std::string_view kPresetPrefix = "INPUT_FRAME_PRESET_";

Eigen::Vector3f FromProto(const v1::Vec3& v) { return {v.x(), v.y(), v.z()}; }

absl::StatusOr<LengthUnit> UnitFromProto(v1::LengthUnit unit) {
  switch (unit) {
    case v1::LENGTH_UNIT_METRE:
      return LengthUnit::kMetre;
    case v1::LENGTH_UNIT_CENTIMETRE:
      return LengthUnit::kCentimetre;
    case v1::LENGTH_UNIT_MILLIMETRE:
      return LengthUnit::kMillimetre;
    case v1::LENGTH_UNIT_INCH:
      return LengthUnit::kInch;
    case v1::LENGTH_UNIT_CMU:
      return LengthUnit::kCmuUnit;
    default:
      return absl::InvalidArgumentError(StrCat("input_frame.unit: unknown value ", static_cast<int>(unit)));
  }
}

absl::StatusOr<UpAxis> UpFromProto(v1::UpAxis up) {
  switch (up) {
    case v1::UP_AXIS_POS_X:
      return UpAxis::kPosX;
    case v1::UP_AXIS_NEG_X:
      return UpAxis::kNegX;
    case v1::UP_AXIS_POS_Y:
      return UpAxis::kPosY;
    case v1::UP_AXIS_NEG_Y:
      return UpAxis::kNegY;
    case v1::UP_AXIS_POS_Z:
      return UpAxis::kPosZ;
    case v1::UP_AXIS_NEG_Z:
      return UpAxis::kNegZ;
    default:
      return absl::InvalidArgumentError(StrCat("input_frame.up: unknown value ", static_cast<int>(up)));
  }
}

v1::LengthUnit ToProto(LengthUnit unit) {
  switch (unit) {
    case LengthUnit::kMetre:
      return v1::LENGTH_UNIT_METRE;
    case LengthUnit::kCentimetre:
      return v1::LENGTH_UNIT_CENTIMETRE;
    case LengthUnit::kMillimetre:
      return v1::LENGTH_UNIT_MILLIMETRE;
    case LengthUnit::kInch:
      return v1::LENGTH_UNIT_INCH;
    case LengthUnit::kCmuUnit:
      return v1::LENGTH_UNIT_CMU;
  }
  return v1::LENGTH_UNIT_UNSPECIFIED;
}

v1::UpAxis ToProto(UpAxis up) { return static_cast<v1::UpAxis>(static_cast<int>(up) + 1); }  // same order

}  // namespace

std::optional<InputFramePreset> PresetFromProto(v1::InputFramePreset preset) {
  if (preset == v1::INPUT_FRAME_PRESET_UNSPECIFIED || !v1::InputFramePreset_IsValid(preset)) return std::nullopt;
  std::string name = v1::InputFramePreset_Name(preset).substr(kPresetPrefix.size());
  std::transform(name.begin(), name.end(), name.begin(),
                 [](unsigned char c) { return c == '_' ? '-' : static_cast<char>(std::tolower(c)); });
  return FindInputFramePreset(name);
}

v1::InputFramePreset PresetToProto(std::string_view name) {
  std::string text(kPresetPrefix);
  for (char c : name) text += c == '-' ? '_' : static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  v1::InputFramePreset preset = v1::INPUT_FRAME_PRESET_UNSPECIFIED;
  return v1::InputFramePreset_Parse(text, &preset) ? preset : v1::INPUT_FRAME_PRESET_UNSPECIFIED;
}

absl::StatusOr<InputFrame> InputFrameFromProto(const v1::InputFrame& proto) {
  InputFrame frame;
  if (proto.preset() != v1::INPUT_FRAME_PRESET_UNSPECIFIED) {
    std::optional<InputFramePreset> preset = PresetFromProto(proto.preset());
    if (!preset)
      return absl::InvalidArgumentError(StrCat("input_frame.preset: unknown value ", static_cast<int>(proto.preset())));
    frame = preset->frame;
  }
  if (proto.unit() != v1::LENGTH_UNIT_UNSPECIFIED) {
    MOCAP_ASSIGN_OR_RETURN(frame.convention.unit, UnitFromProto(proto.unit()));
  }
  if (proto.up() != v1::UP_AXIS_UNSPECIFIED) {
    MOCAP_ASSIGN_OR_RETURN(frame.convention.up, UpFromProto(proto.up()));
  }
  switch (proto.handedness()) {
    case v1::HANDEDNESS_UNSPECIFIED:
      break;
    case v1::HANDEDNESS_RIGHT:
      frame.convention.handedness = Handedness::kRight;
      break;
    case v1::HANDEDNESS_LEFT:
      frame.convention.handedness = Handedness::kLeft;
      break;
    default:
      return absl::InvalidArgumentError(
          StrCat("input_frame.handedness: unknown value ", static_cast<int>(proto.handedness())));
  }
  if (proto.floor_case() == v1::InputFrame::kFloorHeight) frame.floor = {false, proto.floor_height()};
  if (proto.floor_case() == v1::InputFrame::kCalibrateFloor) frame.floor = {proto.calibrate_floor(), 0.0};
  frame.tracked_device = proto.tracked_device();
  frame.device_offset = FromProto(proto.device_offset());
  frame.grip_offset = proto.grip_offset();
  MOCAP_RETURN_IF_ERROR(ValidateInputFrame(frame));
  return frame;
}

v1::InputFrame ToProto(const InputFrame& frame, v1::InputFramePreset preset) {
  v1::InputFrame out;
  out.set_preset(preset);
  out.set_unit(ToProto(frame.convention.unit));
  out.set_up(ToProto(frame.convention.up));
  out.set_handedness(frame.convention.handedness == Handedness::kRight ? v1::HANDEDNESS_RIGHT : v1::HANDEDNESS_LEFT);
  if (frame.floor.calibrate) {
    out.set_calibrate_floor(true);
  } else {
    out.set_floor_height(static_cast<float>(frame.floor.height));
  }
  out.set_tracked_device(frame.tracked_device);
  out.mutable_device_offset()->set_x(frame.device_offset.x());
  out.mutable_device_offset()->set_y(frame.device_offset.y());
  out.mutable_device_offset()->set_z(frame.device_offset.z());
  out.set_grip_offset(frame.grip_offset);
  return out;
}

}  // namespace mocap

#include "client/cli/input_frame_flags.h"

#include <charconv>

#include "motion/frames/frame_transform.h"
#include "proto/convert/input_frame_proto.h"

namespace mocap::cli {
namespace {

std::string PresetNames() {
  std::string names;
  for (const InputFramePreset& preset : InputFramePresets())
    names += (names.empty() ? "" : ", ") + std::string(preset.name);
  return names;
}

void ToDeclared(const FrameTransform& transform, v1::Vec3* v) {
  const Eigen::Vector3f p = transform.PositionFromNative({v->x(), v->y(), v->z()});
  v->set_x(p.x());
  v->set_y(p.y());
  v->set_z(p.z());
}

}  // namespace

void AddInputFrameFlags(CLI::App* command, InputFrameFlags* flags) {
  command->add_option(
      "--input-frame", flags->preset,
      "Convention of the wrist samples, a preset: " + PresetNames() + " (docs/input-conventions.md; default native)");
  command->add_option("--units", flags->units, "Length unit of the samples: m, cm, mm or in (over the preset)");
  command->add_option("--up", flags->up, "Up axis of the samples: +X, -X, +Y, -Y, +Z or -Z (over the preset)");
  command->add_option("--handedness", flags->handedness, "right or left (over the preset)");
  command->add_option("--floor", flags->floor,
                      "The floor's coordinate on the up axis, in --units, or 'calibrate' (from the first second)");
  command
      ->add_option("--device-offset", flags->device_offset,
                   "The tracked point is a device held in the hand: offset X,Y,Z from it to the wrist, in its own "
                   "frame and --units (the CSV then needs the orientation columns)")
      ->expected(3)
      ->delimiter(',');
  command->add_option("--grip-offset", flags->grip_offset,
                      "The tracked point is a device held in the hand, its orientation not given (a phone, a "
                      "controller by position): its distance beyond the wrist along the forearm, in --units "
                      "(about 0.09 m for a phone in a closed grip)");
}

absl::StatusOr<DeclaredInputFrame> ResolveInputFrame(const InputFrameFlags& flags) {
  DeclaredInputFrame declared;
  InputFrame& frame = declared.frame;
  v1::InputFrame& proto = declared.proto;
  if (!flags.preset.empty()) {
    std::optional<InputFramePreset> preset = FindInputFramePreset(flags.preset);
    if (!preset)
      return absl::InvalidArgumentError("--input-frame: unknown preset \"" + flags.preset + "\" (" + PresetNames() +
                                        ")");
    frame = preset->frame;
    proto.set_preset(PresetToProto(preset->name));
  }
  if (!flags.units.empty()) {
    std::optional<LengthUnit> unit = ParseUnit(flags.units);
    if (!unit) return absl::InvalidArgumentError("--units: expected m, cm, mm or in, not \"" + flags.units + "\"");
    frame.convention.unit = *unit;
  }
  if (!flags.up.empty()) {
    std::optional<UpAxis> up = ParseUpAxis(flags.up);
    if (!up) return absl::InvalidArgumentError("--up: expected +X, -X, +Y, -Y, +Z or -Z, not \"" + flags.up + "\"");
    frame.convention.up = *up;
  }
  if (!flags.handedness.empty()) {
    std::optional<Handedness> handedness = ParseHandedness(flags.handedness);
    if (!handedness)
      return absl::InvalidArgumentError("--handedness: expected right or left, not \"" + flags.handedness + "\"");
    frame.convention.handedness = *handedness;
  }
  if (flags.floor == "calibrate") {
    frame.floor = {true, 0.0};
  } else if (!flags.floor.empty()) {
    double height = 0.0;
    const auto [end, error] = std::from_chars(flags.floor.data(), flags.floor.data() + flags.floor.size(), height);
    if (error != std::errc() || end != flags.floor.data() + flags.floor.size()) {
      return absl::InvalidArgumentError("--floor: expected a number or 'calibrate', not \"" + flags.floor + "\"");
    }
    frame.floor = {false, height};
  }
  if (flags.device_offset.size() == 3) {
    frame.tracked_device = true;
    frame.device_offset = {flags.device_offset[0], flags.device_offset[1], flags.device_offset[2]};
  }
  frame.grip_offset = flags.grip_offset;
  if (absl::Status valid = ValidateInputFrame(frame); !valid.ok()) return valid;
  // The resolved frame in full, so the server reads exactly what the CLI converted with.
  const v1::InputFramePreset preset = proto.preset();
  proto = ToProto(frame, preset);
  return declared;
}

absl::Status ToDeclaredFrame(const InputFrame& frame, std::vector<v1::WristSample>* samples) {
  if (frame.tracked_device) {
    return absl::InvalidArgumentError(
        "--device-offset needs each device's orientation: give --csv with the orientation "
        "columns (BVH wrists are wrist joints already)");
  }
  if (frame.grip_offset != 0.0f) {
    return absl::InvalidArgumentError(
        "--grip-offset is for devices held in the hands (--csv): BVH wrists are wrist joints already");
  }
  const FrameTransform transform(frame.convention, frame.floor.calibrate ? 0.0 : frame.floor.height);
  for (v1::WristSample& sample : *samples) {
    ToDeclared(transform, sample.mutable_left());
    ToDeclared(transform, sample.mutable_right());
  }
  return absl::OkStatus();
}

}  // namespace mocap::cli

#include "motion/frames/input_frame.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>

#include "motion/core/str_cat.h"

namespace mocap {
namespace {

constexpr double kMaxFloorMetres = 10000.0;  // as the samples' own coordinate limit
constexpr double kMaxDeviceOffsetMetres = 0.5;

constexpr FrameConvention kYUpRightMetres{LengthUnit::kMetre, UpAxis::kPosY, Handedness::kRight};
constexpr FloorSpec kFloorAtZero{false, 0.0};
constexpr FloorSpec kCalibrate{true, 0.0};

const std::array<InputFramePreset, 9> kPresets = {{
    {"native", "metres, right-handed, Y up, floor at y = 0 (the server's own frame)", {kYUpRightMetres, kFloorAtZero}},
    {"openxr-local-floor",
     "OpenXR LOCAL_FLOOR / STAGE space: metres, right-handed, Y up, floor at y = 0",
     {kYUpRightMetres, kFloorAtZero}},
    {"openxr-local",
     "OpenXR LOCAL space: metres, right-handed, Y up, origin at the head at start: floor calibrated",
     {kYUpRightMetres, kCalibrate}},
    {"webxr-local-floor",
     "WebXR 'local-floor': metres, right-handed, Y up, floor at y = 0",
     {kYUpRightMetres, kFloorAtZero}},
    {"webxr-local",
     "WebXR 'local': metres, right-handed, Y up, origin near the head at start: floor calibrated",
     {kYUpRightMetres, kCalibrate}},
    {"arkit-world",
     "ARKit world space: metres, right-handed, Y up (gravity), origin where the session started: "
     "floor calibrated",
     {kYUpRightMetres, kCalibrate}},
    {"unity",
     "Unity world: metres, left-handed, Y up, floor at y = 0 (an XR rig with a floor origin)",
     {{LengthUnit::kMetre, UpAxis::kPosY, Handedness::kLeft}, kFloorAtZero}},
    {"unreal",
     "Unreal Engine world: centimetres, left-handed, Z up, floor at z = 0",
     {{LengthUnit::kCentimetre, UpAxis::kPosZ, Handedness::kLeft}, kFloorAtZero}},
    {"mediapipe-world",
     "MediaPipe pose world landmarks: metres, right-handed (x right, y down, z away from the camera), "
     "origin between the hips: floor calibrated; the origin follows the hips, so the body does not "
     "travel",
     {{LengthUnit::kMetre, UpAxis::kNegY, Handedness::kRight}, kCalibrate}},
}};

bool SameName(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
         });
}

}  // namespace

bool IsNativeFrame(const InputFrame& frame) {
  const FrameConvention& c = frame.convention;
  return c.unit == LengthUnit::kMetre && c.up == UpAxis::kPosY && c.handedness == Handedness::kRight &&
         !frame.floor.calibrate && frame.floor.height == 0.0;
}

absl::Status ValidateInputFrame(const InputFrame& frame) {
  const double metres = MetresPerUnit(frame.convention.unit);
  if (!frame.floor.calibrate && !(std::abs(frame.floor.height * metres) <= kMaxFloorMetres)) {
    return absl::InvalidArgumentError(StrCat("input_frame.floor_height ", frame.floor.height, " ",
                                             UnitName(frame.convention.unit), " is not a finite height within ",
                                             kMaxFloorMetres, " m"));
  }
  if (frame.tracked_device) {
    const double length = frame.device_offset.norm() * metres;
    if (!(length <= kMaxDeviceOffsetMetres)) {
      return absl::InvalidArgumentError(StrCat("input_frame.device_offset is ", length, " m long (at most ",
                                               kMaxDeviceOffsetMetres, " m from the device to the wrist; units are ",
                                               UnitName(frame.convention.unit), ")"));
    }
  }
  if (frame.grip_offset != 0.0f) {
    const double grip = frame.grip_offset * metres;
    if (!(grip > 0.0 && grip <= kMaxGripOffsetMetres)) {
      return absl::InvalidArgumentError(StrCat("input_frame.grip_offset is ", grip, " m (from the wrist to where the ",
                                               "device is held: more than 0 and at most ", kMaxGripOffsetMetres,
                                               " m; units are ", UnitName(frame.convention.unit), ")"));
    }
    if (frame.tracked_device) {
      return absl::InvalidArgumentError(
          "input_frame.grip_offset with tracked_device: the device's orientation and device_offset already give "
          "the wrist");
    }
  }
  return absl::OkStatus();
}

std::span<const InputFramePreset> InputFramePresets() { return kPresets; }

std::optional<InputFramePreset> FindInputFramePreset(std::string_view name) {
  for (const InputFramePreset& preset : kPresets) {
    if (SameName(preset.name, name)) return preset;
  }
  return std::nullopt;
}

}  // namespace mocap

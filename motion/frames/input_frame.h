// What a caller declares about its wrist samples (issue #12, SessionConfig.input_frame): the
// frame convention, where the floor is, and whether the tracked point is the wrist joint or a
// device held in the hand. Named presets for the common sources.
#pragma once

#include <optional>
#include <span>
#include <string_view>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "absl/status/status.h"
#include "motion/frames/frame_convention.h"

namespace mocap {

struct FloorSpec {
  // Estimate the floor from the first second of input (InputMonitor: a standing performer's
  // wrists hang at a known fraction of body height) instead of taking `height`.
  bool calibrate = false;
  // The floor's coordinate on the caller's up axis, caller units (FrameTransform).
  double height = 0.0;
};

struct InputFrame {
  FrameConvention convention;
  FloorSpec floor;
  // The tracked point is a device held in the hand: each sample then carries the device's
  // orientation, and the wrist joint is at device position + orientation · device_offset.
  bool tracked_device = false;
  Eigen::Vector3f device_offset = Eigen::Vector3f::Zero();  // device frame, caller units
  // The tracked point is a device held in the hand whose orientation is not sent (a phone, a
  // controller tracked by position): this far beyond the wrist joint along the forearm, caller
  // units (0: the samples are the wrists; not with tracked_device, whose offset says it exactly).
  float grip_offset = 0.0f;
};

inline constexpr double kMaxGripOffsetMetres = 0.3;

// The server's own frame (metres, right-handed, Y up, declared floor at 0): nothing to convert
// on the way out.
bool IsNativeFrame(const InputFrame& frame);

// InvalidArgument naming the field: a floor height that is not finite or beyond 10 km, a device
// offset that is not finite or longer than 0.5 m (a hand is not that long), a grip offset that is
// negative, beyond 0.3 m or given with a tracked device.
absl::Status ValidateInputFrame(const InputFrame& frame);

// The wrist joint of a tracked device, in the caller's frame and units.
inline Eigen::Vector3f DeviceToWrist(const Eigen::Vector3f& position, const Eigen::Quaternionf& orientation,
                                     const Eigen::Vector3f& offset) {
  return position + orientation * offset;
}

struct InputFramePreset {
  std::string_view name;         // as the CLI takes it, e.g. "openxr-local-floor"
  std::string_view description;  // the assumption, one line (docs/input-conventions.md)
  InputFrame frame;
};
// Every preset, in a fixed order: native, openxr-local-floor, openxr-local, webxr-local-floor,
// webxr-local, arkit-world, unity, unreal, mediapipe-world.
std::span<const InputFramePreset> InputFramePresets();
// A preset by name (any case); nullopt when there is none.
std::optional<InputFramePreset> FindInputFramePreset(std::string_view name);

}  // namespace mocap

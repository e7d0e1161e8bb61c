// `mocap reconstruct`'s input-frame flags (issue #12): a preset (--input-frame) and explicit
// --units, --up, --handedness, --floor, --device-offset over it.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "absl/status/statusor.h"
#include "mocap/v1/reconstruction.pb.h"
#include "motion/frames/input_frame.h"

namespace mocap::cli {

struct InputFrameFlags {
  std::string preset, units, up, handedness, floor;
  std::vector<float> device_offset;  // 3 values when given
  float grip_offset = 0.0f;
};

void AddInputFrameFlags(CLI::App* command, InputFrameFlags* flags);

struct DeclaredInputFrame {
  InputFrame frame;      // resolved: the preset with the flags over it
  v1::InputFrame proto;  // SessionConfig.input_frame
};
// InvalidArgument naming the flag for an unknown preset, unit, axis or handedness, or a floor that
// is neither a number nor "calibrate".
absl::StatusOr<DeclaredInputFrame> ResolveInputFrame(const InputFrameFlags& flags);

// Native wrists (metres, Y up, floor at 0: a BVH clip's forward kinematics) rewritten in the
// declared frame, as a tracker in that frame would send them (a calibrated floor stays where the
// clip's is). InvalidArgument for a device offset (BVH wrists have no device orientations) or a
// grip offset (they are wrists, not devices).
absl::Status ToDeclaredFrame(const InputFrame& frame, std::vector<v1::WristSample>* samples);

}  // namespace mocap::cli

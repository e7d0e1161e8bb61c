// The input frame of a reconstruction session (input_frame.proto) <-> motion/frames: the server
// reads a client's declaration with it, the `mocap` CLI writes one.
#pragma once

#include <optional>

#include "absl/status/statusor.h"
#include "mocap/v1/reconstruction.pb.h"
#include "motion/frames/input_frame.h"

namespace mocap {

// The preset (if any) with the explicit fields over it. InvalidArgument naming the field for an
// unknown enum value, a floor height or device offset out of range.
absl::StatusOr<InputFrame> InputFrameFromProto(const v1::InputFrame& proto);
// `frame` written out field by field (SessionStarted.config.input_frame), keeping `preset`.
v1::InputFrame ToProto(const InputFrame& frame, v1::InputFramePreset preset);
// The motion/frames preset of a proto preset ("openxr-local-floor" for
// INPUT_FRAME_PRESET_OPENXR_LOCAL_FLOOR); nullopt for UNSPECIFIED or an unknown value.
std::optional<InputFramePreset> PresetFromProto(v1::InputFramePreset preset);
// The proto preset of a motion/frames preset name (the inverse); UNSPECIFIED for an unknown name.
v1::InputFramePreset PresetToProto(std::string_view name);

}  // namespace mocap

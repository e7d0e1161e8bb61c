// The client's input frame (input_frame.proto) <-> motion/frames, and the conversion of replies
// back into the declared frame. The output conversion works on the wire messages, so it applies
// to whatever skeleton and frames a session answers with (the database's rig or another).
#pragma once

#include "absl/status/statusor.h"
#include "mocap/v1/reconstruction.pb.h"
#include "motion/frames/frame_transform.h"
#include "motion/frames/input_frame.h"
#include "motion/frames/input_monitor.h"

namespace mocap {

// The preset (if any) with the explicit fields over it. InvalidArgument naming the field for an
// unknown enum value, a floor height or device offset out of range.
absl::StatusOr<InputFrame> InputFrameFromProto(const v1::InputFrame& proto);
// `frame` written out field by field (SessionStarted.config.input_frame), keeping `preset`.
v1::InputFrame ToProto(const InputFrame& frame, v1::InputFramePreset preset);
// The motion/frames preset of a proto preset ("openxr-local-floor" for
// INPUT_FRAME_PRESET_OPENXR_LOCAL_FLOOR); nullopt for UNSPECIFIED or an unknown value.
std::optional<InputFramePreset> PresetFromProto(v1::InputFramePreset preset);

// Samples on their way in: the declared frame and the transform to native coordinates (its floor
// is the declared one, or 0 while the floor is being calibrated).
struct InputConversion {
  InputFrame frame;
  FrameTransform transform;
};

// Native replies into the caller's frame: skeleton offsets and end sites; a frame's root, pelvis,
// ankle and wrist positions, every rotation (R' = C⁻¹·R·C) and the diagnostics' distances.
void ToCallerFrame(const FrameTransform& transform, v1::Skeleton* skeleton);
void ToCallerFrame(const FrameTransform& transform, v1::Frame* frame);

v1::InputWarning ToProto(const InputWarning& warning);

}  // namespace mocap

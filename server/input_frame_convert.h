// The client's input frame on the server: samples into native metres (InputConversion) and
// replies back into the declared frame. The output conversion works on the wire messages, so it applies
// to whatever skeleton and frames a session answers with (the database's rig or another).
#pragma once

#include "mocap/v1/reconstruction.pb.h"
#include "motion/frames/frame_transform.h"
#include "motion/frames/input_frame.h"
#include "motion/frames/input_monitor.h"
#include "proto/convert/input_frame_proto.h"

namespace mocap {

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

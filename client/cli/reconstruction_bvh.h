// A streamed reconstruction (SessionStarted + frames) as BVH text: the session's skeleton in
// metres, Y up, at the session's frame rate; root with 6 channels, other joints ZXY rotations. A
// pelvis below other joints (an extra root) also gets position channels and carries the motion,
// with the joints above it held still and the root at the origin. A body that grew while the
// stream learned the performer's size (Frame.body_scale) is written at the size it reached, each
// earlier frame's pelvis over the same ground point, its height in the final body's proportion.
#pragma once

#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "mocap/v1/reconstruction.pb.h"

namespace mocap::cli {

// Frame.body_scale, its unset 0 read as 1: the frame's bones are the skeleton's times it.
inline float BodyScale(const v1::Frame& frame) { return frame.body_scale() > 0.0f ? frame.body_scale() : 1.0f; }

// InvalidArgument when a frame's rotations do not match the skeleton.
absl::StatusOr<std::string> ReconstructionBvh(const v1::SessionStarted& started, const std::vector<v1::Frame>& frames);

}  // namespace mocap::cli

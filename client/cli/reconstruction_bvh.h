// A streamed reconstruction (SessionStarted + frames) as BVH text: the session's skeleton in
// metres, Y up, at the session's frame rate; root with 6 channels, other joints ZXY rotations. A
// pelvis below other joints (an extra root) also gets position channels and carries the motion,
// with the joints above it held still and the root at the origin.
#pragma once

#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "mocap/v1/reconstruction.pb.h"

namespace mocap::cli {

// InvalidArgument when a frame's rotations do not match the skeleton.
absl::StatusOr<std::string> ReconstructionBvh(const v1::SessionStarted& started, const std::vector<v1::Frame>& frames);

}  // namespace mocap::cli

// OUTPUT.json of `mocap reconstruct`: the call's whole answer as one JSON object, the text
// Json(answer) gives (client/cli/cli_common.h), written a frame at a time. Converted whole,
// protobuf's JSON printer first builds a tree of every field of every frame: on a 1,000-joint
// target rig a 600-frame answer took 570 MB and most of the client's CPU (allocation and page
// faults), and eight such clients beside a server slowed its other tenants (issue #24).
#pragma once

#include <filesystem>
#include <vector>

#include "absl/status/status.h"
#include "mocap/v1/reconstruction.pb.h"

namespace mocap::cli {

// `answer` without its frames (InvalidArgument if it has any) and the frames apart, in order.
absl::Status WriteReconstructionJson(const std::filesystem::path& path, const v1::ReconstructTrajectoryResponse& answer,
                                     const std::vector<v1::Frame>& frames);

}  // namespace mocap::cli

// OUTPUT.json of `mocap reconstruct`: the call's whole answer as one JSON object, the text
// Json(answer) gives (client/cli/cli_common.h), written a frame at a time. Converted whole,
// protobuf's JSON printer first builds a tree of every field of every frame: on a 1,000-joint
// target rig a 600-frame answer took 570 MB and most of the client's CPU (allocation and page
// faults), and eight such clients beside a server slowed its other tenants (issue #24). A frame's
// rotations (one per target-rig joint, nearly all of its text) are written apart from the
// printer, in its very text: through it they still took two thirds of the client's CPU.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "mocap/v1/reconstruction.pb.h"

namespace mocap::cli {

// `answer` without its frames (InvalidArgument if it has any) and the frames apart, in order.
// Each frame's rotations are taken out while its other fields are printed, and put back.
absl::Status WriteReconstructionJson(const std::filesystem::path& path, const v1::ReconstructTrajectoryResponse& answer,
                                     std::vector<v1::Frame>& frames);

// protobuf's JSON text of a float (its SimpleFtoa: 6 significant digits where they read back as
// the same float, else 9; NaN and the infinities quoted as the JSON mapping says), without printf.
void AppendJsonFloat(float value, std::string& out);

}  // namespace mocap::cli

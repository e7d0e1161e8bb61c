// `mocap reconstruct --target-rig AVATAR.bvh`: the avatar's BVH sent as SessionConfig.target_rig,
// and the answer written back as BVH on that file's own rig (its joint order, channels, unit and
// up axis), so it opens on the avatar like its own animations.
#pragma once

#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "mocap/v1/reconstruction.pb.h"

namespace mocap::cli {

// The file's text cut to what the server takes (target_rig.proto: the hierarchy and frames, at
// most `max_bytes` and 2,000 frames; the analysis needs no more).
absl::StatusOr<std::string> TargetRigText(const std::string& path, size_t max_bytes);

// The session's frames on the target rig, written in the rig file's conventions. The file is
// analysed again here (the same analysis as the server's) for its unit and up axis.
// InvalidArgument when the frames do not animate that rig.
absl::StatusOr<std::string> RetargetedBvhText(const std::string& target_rig_text, const v1::SessionStarted& started,
                                              const std::vector<v1::Frame>& frames);

}  // namespace mocap::cli

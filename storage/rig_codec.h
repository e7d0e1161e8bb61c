// RigModel <-> JSON text, as kept in the databases.rig column.
#pragma once

#include <string>

#include "absl/status/statusor.h"
#include "motion/preprocess/clip_preprocessor.h"

namespace mocap::storage {

std::string EncodeRig(const RigModel& rig);
// DataLoss when the text is not a rig this build understands.
absl::StatusOr<RigModel> DecodeRig(const std::string& text);

}  // namespace mocap::storage

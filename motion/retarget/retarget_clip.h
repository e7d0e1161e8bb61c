// A clip captured on another rig as motion of a database's rig (issue #22: databases built from
// several rigs). Every frame goes through the Retargeter (landmarks, limb directions, hands and
// feet reached with the database body's own limbs), then back into the database rig's own file
// conventions, so that the import prepares it like any file of that rig.
#pragma once

#include <optional>

#include "absl/status/statusor.h"
#include "motion/bvh/bvh_clip.h"
#include "motion/core/units.h"
#include "motion/preprocess/clip_preprocessor.h"

namespace mocap {

// `clip_unit`: the clip's length unit when declared (else detected from its body). Fails, with
// the analysis' reason, when the clip's rig is not a recognisable humanoid.
absl::StatusOr<BvhClip> RetargetClipOntoRig(const BvhClip& clip, const RigModel& rig,
                                            std::optional<LengthUnit> clip_unit = std::nullopt);

}  // namespace mocap

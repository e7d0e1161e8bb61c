// A clip's body points (docs/method.md B3–B4) as the importer makes them: rig model, prepared clip
// (metres, Y up, 30 fps), forward kinematics, points per frame.
#pragma once

#include <string>

#include "absl/status/statusor.h"
#include "motion/bvh/bvh_clip.h"
#include "motion/preprocess/clip_preprocessor.h"
#include "motion/similarity/pose_index.h"

namespace mocap::testing {

// With a given rig model (e.g. a database's).
absl::StatusOr<ClipPoints> PointsOf(const BvhClip& clip, const RigModel& rig, const BodyPointOptions& options = {});
// With the clip's own rig model, as a query is read.
absl::StatusOr<ClipPoints> QueryPoints(const BvhClip& clip, const BodyPointOptions& options = {});

// A test-name form of a scaling: "BoneDirections", "PerChain", "BodyScale".
std::string ChainScalingTestName(ChainScaling scaling);

}  // namespace mocap::testing

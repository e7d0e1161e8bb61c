#include "tests/support/clip_points.h"

#include "motion/core/status_macros.h"
#include "motion/skeleton/forward_kinematics.h"

namespace mocap::testing {

absl::StatusOr<ClipPoints> PointsOf(const BvhClip& clip, const RigModel& rig, const BodyPointOptions& options) {
  MOCAP_ASSIGN_OR_RETURN(PreparedClip prepared, PrepareClip(clip, rig, {}));
  const GlobalPoses poses = ForwardKinematics(prepared.skeleton, prepared.motion);
  return MakeClipPoints(poses, MakeBodyChains(rig.skeleton, rig.topology), options);
}

absl::StatusOr<ClipPoints> QueryPoints(const BvhClip& clip, const BodyPointOptions& options) {
  MOCAP_ASSIGN_OR_RETURN(RigModel rig, BuildRigModel(clip, {}));
  return PointsOf(clip, rig, options);
}

}  // namespace mocap::testing

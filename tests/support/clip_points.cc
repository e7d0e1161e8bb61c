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

std::string ChainScalingTestName(ChainScaling scaling) {
  std::string name;
  bool upper = true;
  for (char c : ChainScalingName(scaling)) {
    if (c == '-') {
      upper = true;
      continue;
    }
    name += upper ? static_cast<char>(c - 'a' + 'A') : c;
    upper = false;
  }
  return name;
}

}  // namespace mocap::testing

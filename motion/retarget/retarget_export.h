// Retargeted frames as BVH in the caller's own file conventions: the target rig's hierarchy,
// joint order, channels (order and count), length unit and up axis, so the result opens on the
// avatar it was made for (Blender, game engines) like any of its own animations.
#pragma once

#include <vector>

#include "motion/bvh/bvh_clip.h"
#include "motion/reconstruct/body_model.h"
#include "motion/retarget/retarget_rig.h"

namespace mocap {

// `poses`: target joint order, metres, world Y up (Retargeter::Retarget). A pelvis with its own
// position channels carries the motion while the joints above it stay at rest, as captures do.
BvhClip RetargetedToBvh(const RetargetRig& target, const std::vector<BodyPose>& poses, double frame_time);

}  // namespace mocap

// A reconstruction as BVH on the database's rig: the file's own units, up axis and channel
// layout, so it opens beside the database's clips in any tool.
#pragma once

#include <vector>

#include "motion/bvh/bvh_clip.h"
#include "motion/reconstruct/reconstruction_database.h"
#include "motion/reconstruct/reconstruction_session.h"
#include "motion/skeleton/local_motion.h"

namespace mocap {

// Joints above the pelvis (Bandai's joint_Root, an RL_BoneRoot) are bookkeeping nodes that the
// capture keeps still, with the pelvis carrying the motion in its position channels. A body model
// moves them instead (it places the root from the pelvis through fixed offsets), which in a
// viewer shows a root wandering metres away and under the floor. Where the pelvis has position
// channels (all three: give it them with WithPelvisPositionChannels, and write the file with that
// skeleton), this holds those joints at `held_rotations` (per joint; the root's includes any turn
// of the world) with the root at `root_offset`, and gives the pelvis its world motion relative to
// them. World positions of every body joint are unchanged. `motion` is in metres, Y up. Without
// them it changes nothing: a file written with the skeleton's channels could not carry the
// pelvis' translation.
void HoldJointsAbovePelvis(const Skeleton& skeleton, int pelvis, const std::vector<Eigen::Quaternionf>& held_rotations,
                           const Eigen::Vector3f& root_offset, LocalMotion& motion);

// `skeleton` with Xposition Yposition Zposition (ahead of its rotations) on `pelvis` when joints
// sit above it and it lacks any of them (cmu-cc's CC_Base_Hip under RL_BoneRoot has none), so that
// the pelvis can carry the motion while the root stays still. Otherwise `skeleton` as it is.
Skeleton WithPelvisPositionChannels(const Skeleton& skeleton, int pelvis);

// Frames in order (several segments are joined end to end).
BvhClip ReconstructionToBvh(const ReconstructionDatabase& database, const std::vector<ReconstructedFrame>& frames);

}  // namespace mocap

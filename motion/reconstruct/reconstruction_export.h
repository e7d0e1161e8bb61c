// A reconstruction as BVH on the database's rig: the file's own units, up axis and channel
// layout, so it opens beside the database's clips in any tool.
#pragma once

#include <vector>

#include "motion/bvh/bvh_clip.h"
#include "motion/reconstruct/reconstruction_database.h"
#include "motion/reconstruct/reconstruction_session.h"

namespace mocap {

// Frames in order (several segments are joined end to end).
BvhClip ReconstructionToBvh(const ReconstructionDatabase& database, const std::vector<ReconstructedFrame>& frames);

}  // namespace mocap

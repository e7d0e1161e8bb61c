// A streamed reconstruction on the input's clock, for the files that have one frame per frame
// time (BVH): after an input dropout too long to bridge the session starts a new segment and makes
// no frames for the gap, so written as they come the motion after it would play early by the gap's
// length. The gap is filled with the frames a keyframe player would show between its two ends.
#pragma once

#include <optional>
#include <vector>

#include "mocap/v1/reconstruction.pb.h"
#include "motion/core/frame_clock.h"

namespace mocap::cli {

struct FilledTimeline {
  std::vector<v1::Frame> frames;  // every frame time from the first frame's to the last's
  int filled_frames = 0;          // of them made here, not by the session
  int gaps = 0;                   // stretches filled
  int unfilled_gaps = 0;          // longer than kLongestFilledGapSeconds: joined as they come
};

// Where consecutive frames lie more than 1.5 frame times apart, the frame times between them are
// filled (FrameTimesMissing): each joint's rotation slerped and the root, pelvis and body scale
// moved linearly from the frame before the gap to the frame after it (the input said nothing of
// the motion there); the made frames keep the frame before's segment and are marked lost in both
// hands. nullopt when no frame time is missing and no gap is too long to fill (the frames as they
// are are the timeline), or `frame_rate` is not positive.
std::optional<FilledTimeline> FillDropouts(const std::vector<v1::Frame>& frames, double frame_rate);

}  // namespace mocap::cli

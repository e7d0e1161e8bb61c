// DatabaseFrame: what a reconstruction database keeps of a row's A1 features for the query-time
// steps: its ankles (docs/method.md A3's clouds, A7's contact source) and its pelvis (A5's z_R).
// The wrist and ankle features the searches compare live in the two kd-trees' own copies, θ and
// h in the pose rows, and the reference frame mattered only while building: keeping the whole
// FrameFeatures cost 68 bytes more per row (issue #26: database memory per frame).
#pragma once

#include <vector>

#include "motion/preprocess/frame_features.h"

namespace mocap {

struct DatabaseFrame {
  float ankle_position[2][3];  // in the frame's wrist reference frame, metres
  float ankle_velocity[2][3];  // m/s, same frame
  float pelvis_position[3];    // in the reference frame
  float pelvis_rotation[4];    // w, x, y, z, in the reference frame
};

DatabaseFrame ToDatabaseFrame(const FrameFeatures& features);
std::vector<DatabaseFrame> ToDatabaseFrames(const std::vector<FrameFeatures>& features);

}  // namespace mocap

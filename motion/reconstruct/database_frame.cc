#include "motion/reconstruct/database_frame.h"

#include <algorithm>
#include <iterator>

namespace mocap {

DatabaseFrame ToDatabaseFrame(const FrameFeatures& features) {
  DatabaseFrame frame;
  std::copy_n(&features.ankle_position[0][0], 6, &frame.ankle_position[0][0]);
  std::copy_n(&features.ankle_velocity[0][0], 6, &frame.ankle_velocity[0][0]);
  std::copy_n(features.pelvis_position, 3, frame.pelvis_position);
  std::copy_n(features.pelvis_rotation, 4, frame.pelvis_rotation);
  return frame;
}

std::vector<DatabaseFrame> ToDatabaseFrames(const std::vector<FrameFeatures>& features) {
  std::vector<DatabaseFrame> frames;
  frames.reserve(features.size());
  std::transform(features.begin(), features.end(), std::back_inserter(frames), ToDatabaseFrame);
  return frames;
}

}  // namespace mocap

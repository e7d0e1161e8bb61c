// A reconstruction's frames on the input's clock (one frame per frame time): where consecutive
// frames lie further apart than a frame time and a half (an input dropout the session could not
// bridge, which starts a new segment and makes no frames), the frame times between them are
// missing. The BVH `mocap reconstruct` writes fills them, and `mocap view` places the JSON's
// traces and expected errors by the same rule, so the two stay frame for frame.
#pragma once

#include <cmath>

namespace mocap {

// A longer stretch without input (a clock that jumped, a session left open overnight) is not
// filled: ten minutes of frames is already a BVH of hundreds of megabytes.
inline constexpr double kLongestFilledGapSeconds = 600.0;

// Frame times to fill between two frames `gap_seconds` apart on a clock of `frame_time` seconds
// (0 where nothing is missing, the gap is longer than kLongestFilledGapSeconds or either is not a
// finite positive number).
inline long FrameTimesMissing(double gap_seconds, double frame_time) {
  if (!(frame_time > 0.0) || !(gap_seconds <= kLongestFilledGapSeconds)) return 0;
  const double apart = gap_seconds / frame_time;
  return apart > 1.5 && std::isfinite(apart) ? std::lround(apart) - 1 : 0;
}

// Whether the gap is too long to fill (kLongestFilledGapSeconds).
inline bool GapTooLongToFill(double gap_seconds) { return gap_seconds > kLongestFilledGapSeconds; }

}  // namespace mocap

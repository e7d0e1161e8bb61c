#include "motion/bvh/bvh_inspection.h"

#include "motion/bvh/bvh_reader.h"
#include "motion/core/status_macros.h"
#include "motion/skeleton/local_motion.h"

namespace mocap {

absl::StatusOr<BvhInspection> InspectBvhFile(const std::filesystem::path& path, std::optional<LengthUnit> unit) {
  MOCAP_ASSIGN_OR_RETURN(BvhClip clip, ReadBvhFile(path.string()));
  const LocalMotion motion = MotionFromChannels(clip.skeleton, clip.channels, clip.frame_time);
  absl::StatusOr<BodyTopology> analysed = AnalyseBody(clip.skeleton, motion, BodyTopologyOptions{.unit = unit});
  if (!analysed.ok()) {
    return absl::Status(analysed.status().code(), path.string() + ": " + std::string(analysed.status().message()));
  }
  BvhInspection out;
  out.file = path.string();
  out.frames = clip.num_frames();
  out.frame_rate = clip.frame_rate();
  out.duration_seconds = (clip.num_frames() - 1) * clip.frame_time;
  out.skeleton = std::move(clip.skeleton);
  out.topology = std::move(*analysed);
  return out;
}

std::string AxisName(int axis, int sign) { return std::string(sign > 0 ? "+" : "-") + static_cast<char>('X' + axis); }

}  // namespace mocap

// What the importer understands about one BVH file's skeleton: the body analysis (groups,
// landmarks, up axis, units, sizes) with the file's size and timing. `mocapd inspect` prints it.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "absl/status/statusor.h"
#include "motion/core/units.h"
#include "motion/skeleton/body_topology.h"
#include "motion/skeleton/skeleton.h"

namespace mocap {

struct BvhInspection {
  std::string file;
  Skeleton skeleton;  // the file's hierarchy (joint names for the topology's indices)
  int frames = 0;
  double frame_rate = 0.0;
  double duration_seconds = 0.0;
  BodyTopology topology;
};

// Reads and analyses one BVH file; `unit` overrides unit detection. Errors name the file.
absl::StatusOr<BvhInspection> InspectBvhFile(const std::filesystem::path& path, std::optional<LengthUnit> unit = {});

// "+Y", "-Z", ...: an axis index (0..2) with its sign.
std::string AxisName(int axis, int sign);

}  // namespace mocap

// Reader for real-world BVH files (docs/method.md; shared/data/README "What real files throw at an importer").
#pragma once

#include <filesystem>
#include <string_view>

#include "absl/status/statusor.h"
#include "motion/bvh/bvh_clip.h"

namespace mocap {

struct BvhReadLimits {
  int max_frames = 5'000'000;
  double min_frame_time = 1e-4;  // seconds (10 kHz)
  double max_frame_time = 1.0;   // seconds (1 Hz)
};

// Parses BVH text. Accepts any Euler order, 0/3/6 channels on any joint, End Sites, tabs or spaces,
// CRLF, trailing blank lines, "Frame Time: .0333". Every malformed input yields InvalidArgument
// with "SOURCE:LINE: what was expected" — never a partial clip.
absl::StatusOr<BvhClip> ParseBvh(std::string_view text, std::string_view source_name, const BvhReadLimits& limits = {});

// Reads and parses a file; NotFound / PermissionDenied style errors when it cannot be read.
absl::StatusOr<BvhClip> ReadBvhFile(const std::filesystem::path& path, const BvhReadLimits& limits = {});

}  // namespace mocap

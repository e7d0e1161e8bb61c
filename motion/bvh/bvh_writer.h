// Writer for BVH text that reads back identically (shortest round-trip float formatting).
#pragma once

#include <filesystem>
#include <string>

#include "absl/status/status.h"
#include "motion/bvh/bvh_clip.h"

namespace mocap {

// Tab-indented hierarchy, "Frames:" and "Frame Time:" headers, one frame per line, LF endings:
// the layout Blender, MotionBuilder and the CMU tools accept.
std::string FormatBvh(const BvhClip& clip);

// Writes atomically (temporary file, then rename).
absl::Status WriteBvhFile(const BvhClip& clip, const std::filesystem::path& path);

}  // namespace mocap

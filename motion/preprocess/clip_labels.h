// Labels parsed from a clip's file name.
#pragma once

#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace mocap {

using ClipLabels = std::vector<std::pair<std::string, std::string>>;

// Known patterns (shared/data/README):
//   dataset-2_{content}_{style}_{take}.bvh -> set, content, style, take
//   {subject}_{trial}.bvh (CMU)            -> subject, trial
// Anything else -> name = file stem (free-form). `file_name` may include folders and extension.
ClipLabels ParseClipLabels(std::string_view file_name);

// Value of `key`, or empty.
std::string LabelValue(const ClipLabels& labels, std::string_view key);

}  // namespace mocap

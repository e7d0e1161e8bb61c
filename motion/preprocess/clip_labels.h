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

#include <filesystem>
#include <map>

namespace mocap {

// Reads a CMU-style description table ("Subject","Trial #","Motion Description",...) into
// "subject_trial" (as numbers, e.g. "1_1") -> description. Empty map when unreadable.
std::map<std::string, std::string> ReadTrialDescriptions(const std::filesystem::path& csv_path);

// Key into ReadTrialDescriptions' map for a clip's labels ("" when the clip has no subject/trial).
std::string TrialKey(const ClipLabels& labels);

}  // namespace mocap

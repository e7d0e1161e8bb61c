#include "motion/preprocess/clip_labels.h"

#include <filesystem>
#include <regex>

namespace mocap {

ClipLabels ParseClipLabels(std::string_view file_name) {
  const std::string stem = std::filesystem::path(std::string(file_name)).stem().string();
  static const std::regex kBandai(R"(^(dataset-\d+)_(.+)_([A-Za-z]+)_(\d+)$)");
  static const std::regex kCmu(R"(^(\d+)_(\d+)$)");
  std::smatch match;
  if (std::regex_match(stem, match, kBandai)) {
    return {{"set", match[1]}, {"content", match[2]}, {"style", match[3]}, {"take", match[4]}};
  }
  if (std::regex_match(stem, match, kCmu)) {
    return {{"subject", match[1]}, {"trial", match[2]}};
  }
  return {{"name", stem}};
}

std::string LabelValue(const ClipLabels& labels, std::string_view key) {
  for (const auto& [k, v] : labels) {
    if (k == key) return v;
  }
  return {};
}

}  // namespace mocap

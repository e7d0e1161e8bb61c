#include "motion/preprocess/clip_labels.h"

#include <filesystem>
#include <regex>

namespace mocap {

ClipLabels ParseClipLabels(std::string_view file_name) {
  const std::string stem = std::filesystem::path(std::string(file_name)).stem().string();
  static const std::regex kBandai(R"(^(dataset-\d+)_(.+)_([A-Za-z][A-Za-z-]*)_(\d+)$)");
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

#include <fstream>

namespace mocap {
namespace {

std::vector<std::string> SplitCsvLine(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        fields.back() += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        fields.back() += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      fields.emplace_back();
    } else if (c != '\r') {
      fields.back() += c;
    }
  }
  return fields;
}

std::string StripLeadingZeros(const std::string& digits) {
  const size_t first = digits.find_first_not_of('0');
  return first == std::string::npos ? "0" : digits.substr(first);
}

}  // namespace

std::map<std::string, std::string> ReadTrialDescriptions(const std::filesystem::path& csv_path) {
  std::map<std::string, std::string> out;
  std::ifstream in(csv_path);
  std::string line;
  if (!std::getline(in, line)) return out;  // header
  while (std::getline(in, line)) {
    const std::vector<std::string> fields = SplitCsvLine(line);
    if (fields.size() < 3 || fields[0].empty() || fields[1].empty()) continue;
    out[StripLeadingZeros(fields[0]) + "_" + StripLeadingZeros(fields[1])] = fields[2];
  }
  return out;
}

std::string TrialKey(const ClipLabels& labels) {
  const std::string subject = LabelValue(labels, "subject");
  const std::string trial = LabelValue(labels, "trial");
  if (subject.empty() || trial.empty()) return {};
  return StripLeadingZeros(subject) + "_" + StripLeadingZeros(trial);
}

}  // namespace mocap

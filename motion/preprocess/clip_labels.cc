#include "motion/preprocess/clip_labels.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace mocap {

namespace {

bool AllDigits(std::string_view text) {
  return !text.empty() && std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
}

bool IsStyle(std::string_view text) {  // letters and inner hyphens ("not-confident")
  return !text.empty() && std::isalpha(static_cast<unsigned char>(text.front())) &&
         std::all_of(text.begin(), text.end(),
                     [](char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '-'; });
}

std::vector<std::string_view> SplitUnderscores(std::string_view text) {
  std::vector<std::string_view> parts;
  size_t start = 0;
  while (true) {
    const size_t end = text.find('_', start);
    parts.push_back(text.substr(start, end == std::string_view::npos ? std::string_view::npos : end - start));
    if (end == std::string_view::npos) return parts;
    start = end + 1;
  }
}

}  // namespace

ClipLabels ParseClipLabels(std::string_view file_name) {
  const std::string stem = std::filesystem::path(std::string(file_name)).stem().string();
  const std::vector<std::string_view> parts = SplitUnderscores(stem);
  // dataset-N_{content}_{style}_{take}; the content may itself hold underscores.
  if (parts.size() >= 4 && parts[0].starts_with("dataset-") && AllDigits(parts[0].substr(8)) &&
      IsStyle(parts[parts.size() - 2]) && AllDigits(parts.back())) {
    std::string content(parts[1]);
    for (size_t i = 2; i + 2 < parts.size(); ++i) (content += '_') += parts[i];
    if (!content.empty()) {
      return {{"set", std::string(parts[0])},
              {"content", content},
              {"style", std::string(parts[parts.size() - 2])},
              {"take", std::string(parts.back())}};
    }
  }
  if (parts.size() == 2 && AllDigits(parts[0]) && AllDigits(parts[1])) {
    return {{"subject", std::string(parts[0])}, {"trial", std::string(parts[1])}};
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

#include "client/cli/refusal_summary.h"

#include <algorithm>
#include <cctype>
#include <map>

namespace mocap {

namespace {

// The reason with every number replaced by '#'.
std::string Shape(const std::string& reason) {
  std::string shape;
  bool in_number = false;
  for (char c : reason) {
    const bool numeric =
        std::isdigit(static_cast<unsigned char>(c)) || ((c == '.' || c == '-' || c == 'e') && in_number);
    if (numeric) {
      if (!in_number) shape += '#';
    } else {
      shape += c;
    }
    in_number = numeric;
  }
  return shape;
}

// What to do about a group of refusals, by what the server said.
std::string Fix(const std::string& reason) {
  if (reason.find("from the origin") != std::string::npos) {
    return "positions this far from the origin are a game engine's world: add --recenter (the first sample's "
           "wrists move to the origin on the ground plane, their height kept)";
  }
  if (reason.find("apart") != std::string::npos) {
    return "check the declared unit (--units or --input-frame): a centimetre file read as metres puts the wrists "
           "metres apart";
  }
  if (reason.find("orientation") != std::string::npos) {
    return "--device-offset needs each device's orientation: add the columns left_qw..right_qz to the CSV, or "
           "leave --device-offset out";
  }
  if (reason.find("not a finite number") != std::string::npos) return "remove or repair the NaN / inf rows";
  if (reason.find("time") != std::string::npos) return "times must be finite seconds, increasing";
  return "";
}

}  // namespace

std::vector<RefusalGroup> GroupRefusals(const google::protobuf::RepeatedPtrField<v1::SampleRejected>& rejected) {
  std::map<std::string, size_t> index;
  std::vector<RefusalGroup> groups;
  for (const v1::SampleRejected& r : rejected) {
    const auto [it, added] = index.emplace(Shape(r.reason()), groups.size());
    if (added) groups.push_back({r.reason(), 0, r.sample_index()});
    ++groups[it->second].count;
  }
  std::stable_sort(groups.begin(), groups.end(),
                   [](const RefusalGroup& a, const RefusalGroup& b) { return a.count > b.count; });
  return groups;
}

std::string DescribeRefusals(const std::vector<RefusalGroup>& groups, size_t max_groups) {
  std::string text;
  for (size_t i = 0; i < groups.size() && i < max_groups; ++i) {
    const RefusalGroup& g = groups[i];
    text += "  " + std::to_string(g.count) + (g.count == 1 ? " sample" : " samples") + " refused (first: sample " +
            std::to_string(g.first_sample) + "): " + g.reason + "\n";
  }
  if (groups.size() > max_groups) {
    text += "  ... and " + std::to_string(groups.size() - max_groups) + " other reasons (all in the JSON output)\n";
  }
  return text;
}

std::string NothingReconstructedMessage(const std::vector<RefusalGroup>& groups, long samples_sent) {
  long refused = 0;
  for (const RefusalGroup& g : groups) refused += g.count;
  std::string text = "no frame was reconstructed: " + std::to_string(refused) + " of " + std::to_string(samples_sent) +
                     " samples were refused; nothing was written";
  for (const RefusalGroup& g : groups) {
    text += "\n  " + std::to_string(g.count) + " × " + g.reason;
    if (const std::string fix = Fix(g.reason); !fix.empty()) text += "\n    fix: " + fix;
  }
  if (groups.empty()) text += "\n  (the input was too short or too sparse for one frame at the database's rate)";
  return text;
}

}  // namespace mocap

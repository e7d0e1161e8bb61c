// Checks a page in the Prometheus text exposition format (version 0.0.4) as a scraper reads it:
// every line a comment (# HELP / # TYPE) or a sample; each family's HELP and TYPE once, before its
// samples, which are contiguous; sample names of the family (histograms: _bucket, _sum, _count);
// label names and escaped values well formed; values numbers; no series twice.
#pragma once

#include <cstdlib>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace mocap::testing {

// One problem per line found (empty: a valid page).
inline std::vector<std::string> PrometheusTextProblems(const std::string& text) {
  std::vector<std::string> problems;
  auto problem = [&](int line_number, const std::string& what, const std::string& line) {
    problems.push_back("line " + std::to_string(line_number) + ": " + what + ": " + line);
  };
  auto is_name = [](const std::string& name, bool label) {
    if (name.empty()) return false;
    for (size_t i = 0; i < name.size(); ++i) {
      const char c = name[i];
      const bool letter = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' || (!label && c == ':');
      if (!letter && !(i > 0 && c >= '0' && c <= '9')) return false;
    }
    return true;
  };
  if (!text.empty() && text.back() != '\n') problems.push_back("the page does not end in a line feed");
  std::set<std::string> declared;  // families with a TYPE
  std::set<std::string> helped;
  std::set<std::string> finished;  // families whose samples are over
  std::set<std::string> series;
  std::string family, type;
  std::istringstream lines(text);
  int number = 0;
  for (std::string line; std::getline(lines, line);) {
    ++number;
    if (line.empty()) continue;
    if (line[0] == '#') {
      std::istringstream words(line);
      std::string hash, keyword, name, rest;
      words >> hash >> keyword >> name;
      if (keyword != "HELP" && keyword != "TYPE") continue;  // a plain comment
      if (!is_name(name, false)) problem(number, "bad metric name", line);
      if (name != family) {
        if (!family.empty()) finished.insert(family);
        if (finished.count(name) != 0) problem(number, "family declared again after its samples", line);
        family = name;
        type.clear();
      }
      if (keyword == "HELP" && !helped.insert(name).second) problem(number, "second HELP", line);
      if (keyword == "TYPE") {
        words >> type;
        if (type != "counter" && type != "gauge" && type != "histogram" && type != "summary" && type != "untyped")
          problem(number, "unknown type", line);
        if (!declared.insert(name).second) problem(number, "second TYPE", line);
      }
      continue;
    }
    // A sample: name, optional {labels}, value.
    size_t at = 0;
    while (at < line.size() && line[at] != '{' && line[at] != ' ') ++at;
    const std::string name = line.substr(0, at);
    if (!is_name(name, false)) problem(number, "bad sample name", line);
    std::string base = name;
    if (type == "histogram") {
      for (const char* suffix : {"_bucket", "_sum", "_count"}) {
        const std::string s = suffix;
        if (base.size() > s.size() && base.compare(base.size() - s.size(), s.size(), s) == 0) {
          base.resize(base.size() - s.size());
          break;
        }
      }
    }
    if (base != family || declared.count(family) == 0) problem(number, "sample outside its family's TYPE", line);
    std::string labels;
    if (at < line.size() && line[at] == '{') {
      const size_t open = at++;
      for (;;) {
        size_t name_end = at;
        while (name_end < line.size() && line[name_end] != '=' && line[name_end] != '}') ++name_end;
        if (name_end < line.size() && line[name_end] == '}' && name_end == at) {  // {} or a trailing comma
          at = name_end + 1;
          break;
        }
        if (name_end + 1 >= line.size() || line[name_end] != '=' || line[name_end + 1] != '"' ||
            !is_name(line.substr(at, name_end - at), true)) {
          problem(number, "bad label", line);
          at = line.size();
          break;
        }
        at = name_end + 2;
        bool closed = false;
        while (at < line.size()) {
          if (line[at] == '\\') {
            if (at + 1 >= line.size() || (line[at + 1] != '\\' && line[at + 1] != '"' && line[at + 1] != 'n'))
              problem(number, "bad escape in a label value", line);
            at += 2;
          } else if (line[at] == '"') {
            closed = true;
            ++at;
            break;
          } else {
            ++at;
          }
        }
        if (!closed) {
          problem(number, "unterminated label value", line);
          break;
        }
        if (at < line.size() && line[at] == ',') ++at;
        if (at < line.size() && line[at] == '}') {
          ++at;
          break;
        }
      }
      labels = line.substr(open, at - open);
    }
    if (at >= line.size() || line[at] != ' ') {
      problem(number, "no value", line);
      continue;
    }
    const std::string value = line.substr(at + 1);
    char* end = nullptr;
    std::strtod(value.c_str(), &end);
    if (value.empty() || (end != value.c_str() + value.size() && value != "+Inf" && value != "-Inf" && value != "NaN"))
      problem(number, "value is not a number", line);
    if (!series.insert(name + labels).second) problem(number, "the same series twice", line);
  }
  return problems;
}

}  // namespace mocap::testing

#include "eval/html_report.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "eval/report_player_scenes.h"
#include "eval/svg_chart.h"
#include "html_view/text_file.h"
#include "html_view/view_page.h"
#include "motion/core/str_cat.h"

namespace mocap::eval {
namespace {

using html_view::HtmlEscape;
using Json = nlohmann::json;

constexpr std::string_view kReportCss =
    "table{border-collapse:collapse;margin:8px 0 20px;font-variant-numeric:tabular-nums}"
    "th,td{border:1px solid #d4d9e0;padding:4px 8px;text-align:right}th:first-child,td:first-child{text-align:left}"
    "thead th{background:#e9edf2}caption{text-align:left;font-weight:600;padding:4px 0}"
    ".plots{display:flex;flex-wrap:wrap;gap:16px}figure{margin:0;background:#fff;border:1px solid #d4d9e0;padding:8px}"
    "figcaption{color:#5a6472;font-size:13px}dt{font-weight:600;float:left;clear:left;margin-right:8px}dd{margin:0 0 "
    "2px}";

// The usual metrics first, in reading order; others (new ones) after them by name.
constexpr std::string_view kMetricOrder[] = {"mpjpe_cm",
                                             "lower_body_mpjpe_cm",
                                             "upper_body_mpjpe_cm",
                                             "pelvis_error_cm",
                                             "ankle_error_cm",
                                             "wrist_error_cm",
                                             "joint_angle_error_deg",
                                             "joint_angle_rms_deg",
                                             "foot_skate_cm_per_frame",
                                             "truth_foot_skate_cm_per_frame",
                                             "jitter_m_per_s3",
                                             "truth_jitter_m_per_s3",
                                             "frames_per_second",
                                             "frames",
                                             "planted_foot_frames"};

// "lower_body_mpjpe_cm" → "lower body MPJPE (cm)".
std::string Label(std::string name) {
  static const std::pair<std::string_view, std::string_view> kUnits[] = {
      {"_cm_per_frame", " (cm/frame)"}, {"_m_per_s3", " (m/s³)"}, {"_cm", " (cm)"}, {"_deg", " (°)"}};
  std::string unit;
  for (const auto& [suffix, text] : kUnits) {
    if (name.size() > suffix.size() && name.ends_with(suffix)) {
      name.resize(name.size() - suffix.size());
      unit = text;
      break;
    }
  }
  std::replace(name.begin(), name.end(), '_', ' ');
  for (size_t at = name.find("mpjpe"); at != std::string::npos; at = name.find("mpjpe", at))
    name.replace(at, 5, "MPJPE");
  return name + unit;
}

std::string Cell(const Json& value) {
  if (value.is_number()) {
    const double v = value.get<double>();
    char text[48];
    if (v == std::floor(v) && std::abs(v) < 1e15)
      std::snprintf(text, sizeof text, "%.0f", v);
    else
      std::snprintf(text, sizeof text, std::abs(v) >= 100 ? "%.1f" : "%.3g", v);
    return text;
  }
  if (value.is_string()) return HtmlEscape(value.get<std::string>());
  if (value.is_null()) return "";
  return HtmlEscape(value.dump());
}

bool IsScalar(const Json& v) { return v.is_primitive(); }

std::string Table(const std::string& caption, const std::vector<std::string>& header,
                  const std::vector<std::vector<std::string>>& rows) {
  std::string html = StrCat("<table><caption>", HtmlEscape(caption), "</caption><thead><tr>");
  for (const std::string& h : header) html += StrCat("<th>", HtmlEscape(h), "</th>");
  html += "</tr></thead><tbody>";
  for (const auto& row : rows) {
    html += "<tr>";
    for (const std::string& cell : row) html += StrCat("<td>", cell, "</td>");
    html += "</tr>";
  }
  return html + "</tbody></table>\n";
}

// Runs in reading order: the "main" group first ("full" leading), then each ablation group by its value.
std::vector<std::string> RunOrder(const Json& experiments) {
  std::vector<std::string> names;
  for (const auto& [name, run] : experiments.items()) names.push_back(name);
  auto key = [&](const std::string& name) {
    const Json& run = experiments[name];
    const std::string group = run.value("group", std::string());
    return std::make_tuple(group != "main", group, name != "full", run.value("x", 0.0), name);
  };
  std::sort(names.begin(), names.end(), [&](const std::string& a, const std::string& b) { return key(a) < key(b); });
  return names;
}

std::vector<std::string> MetricColumns(const Json& experiments) {
  std::set<std::string> present;
  for (const auto& [name, run] : experiments.items()) {
    if (run.contains("overall") && run["overall"].is_object()) {
      for (const auto& [metric, value] : run["overall"].items()) present.insert(metric);
    }
  }
  std::vector<std::string> columns;
  for (std::string_view known : kMetricOrder) {
    if (present.erase(std::string(known))) columns.emplace_back(known);
  }
  columns.insert(columns.end(), present.begin(), present.end());
  return columns;
}

std::string SummaryTable(const Json& experiments) {
  const std::vector<std::string> metrics = MetricColumns(experiments);
  std::vector<std::string> header = {"run", "group", "value"};
  for (const std::string& m : metrics) header.push_back(Label(m));
  std::vector<std::vector<std::string>> rows;
  for (const std::string& name : RunOrder(experiments)) {
    const Json& run = experiments[name];
    const Json overall = run.value("overall", Json::object());
    std::vector<std::string> row = {HtmlEscape(name), Cell(run.value("group", Json())),
                                    run.value("group", std::string()) == "main" ? "" : Cell(run.value("x", Json()))};
    for (const std::string& m : metrics) row.push_back(Cell(overall.value(m, Json())));
    rows.push_back(std::move(row));
  }
  return Table("Every run, over all test clips", header, rows);
}

// MPJPE per content type (rows) for the main runs (columns).
std::string PerContentTable(const Json& experiments) {
  std::vector<std::string> runs;
  std::set<std::string> contents;
  for (const std::string& name : RunOrder(experiments)) {
    const Json& run = experiments[name];
    if (run.value("group", std::string()) != "main" || !run.contains("by_content")) continue;
    runs.push_back(name);
    for (const auto& [content, m] : run["by_content"].items()) contents.insert(content);
  }
  if (runs.empty()) return "";
  std::vector<std::string> header = {"content type"};
  header.insert(header.end(), runs.begin(), runs.end());
  std::vector<std::vector<std::string>> rows;
  for (const std::string& content : contents) {
    std::vector<std::string> row = {HtmlEscape(content)};
    for (const std::string& run : runs) {
      const Json by_content = experiments[run]["by_content"];
      row.push_back(by_content.contains(content) ? Cell(by_content[content].value("mpjpe_cm", Json())) : "");
    }
    rows.push_back(std::move(row));
  }
  return Table("MPJPE (cm) per content type", header, rows);
}

// The report's other members, whatever they are: scalars as a list, objects of scalars and arrays
// of objects as tables.
std::string OtherSections(const Json& report) {
  std::string facts, tables;
  for (const auto& [name, value] : report.items()) {
    if (name == "experiments") continue;
    if (IsScalar(value) || (value.is_array() && std::all_of(value.begin(), value.end(), IsScalar))) {
      std::string text;
      if (value.is_array()) {
        for (const Json& v : value) text += (text.empty() ? "" : ", ") + Cell(v);
      } else {
        text = Cell(value);
      }
      facts += StrCat("<dt>", HtmlEscape(Label(name)), "</dt><dd>", text, "</dd>");
    } else if (value.is_object()) {
      std::vector<std::vector<std::string>> rows;
      for (const auto& [key, v] : value.items()) rows.push_back({HtmlEscape(Label(key)), Cell(v)});
      tables += Table(Label(name), {"", "value"}, rows);
    } else if (value.is_array() && !value.empty() && value.front().is_object()) {
      std::vector<std::string> columns;
      for (const auto& [key, v] : value.front().items()) columns.push_back(key);
      std::vector<std::vector<std::string>> rows;
      for (const Json& item : value) {
        std::vector<std::string> row;
        for (const std::string& c : columns) row.push_back(item.is_object() ? Cell(item.value(c, Json())) : "");
        rows.push_back(std::move(row));
      }
      std::vector<std::string> header;
      for (const std::string& c : columns) header.push_back(Label(c));
      tables += Table(Label(name), header, rows);
    }
  }
  return StrCat("<dl>", facts, "</dl>\n", tables);
}

// Position error per body part (the metrics named *_mpjpe_cm or *_error_cm, and MPJPE over all
// joints) for the main runs: a bar chart made here from the report's figures.
std::string BodyPartChart(const Json& experiments) {
  std::vector<std::string> metrics;
  for (const std::string& m : MetricColumns(experiments)) {
    if (m.rfind("truth_", 0) != 0 && (m == "mpjpe_cm" || m.ends_with("_mpjpe_cm") || m.ends_with("_error_cm")))
      metrics.push_back(m);
  }
  std::vector<Series> series;
  for (const std::string& name : RunOrder(experiments)) {
    const Json& run = experiments[name];
    if (run.value("group", std::string()) != "main") continue;
    Series s{name, {}};
    for (const std::string& m : metrics) {
      const Json value = run.value("overall", Json::object()).value(m, Json());
      s.values.push_back(value.is_number() ? value.get<double>() : 0.0);
    }
    series.push_back(std::move(s));
  }
  if (metrics.empty() || series.empty()) return "";
  std::vector<std::string> categories;
  for (const std::string& m : metrics) {
    std::string label = m == "mpjpe_cm" ? "all joints" : Label(m.substr(0, m.size() - 3));  // without " (cm)"
    for (const char* word : {" MPJPE", " error"}) {
      if (label.ends_with(word)) label.resize(label.size() - std::string_view(word).size());
    }
    categories.push_back(label);
  }
  return StrCat("<figure>", BarChartSvg("Position error per body part", "error (cm)", categories, series),
                "<figcaption>per body part, from report.json</figcaption></figure>\n");
}

std::string Plots(const std::filesystem::path& plots_dir, const Json& experiments) {
  std::vector<std::filesystem::path> files;
  std::error_code ignored;
  for (const auto& entry : std::filesystem::directory_iterator(plots_dir, ignored)) {
    if (entry.path().extension() == ".svg") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  std::string html = "<h2>Plots</h2>\n<div class=\"plots\">" + BodyPartChart(experiments);
  for (const auto& file : files) {
    absl::StatusOr<std::string> svg = html_view::ReadTextFile(file);
    if (!svg.ok()) continue;
    const size_t start = svg->find("<svg");  // our own charts: inline as they are, without an XML prolog
    if (start == std::string::npos) continue;
    html += StrCat("<figure>", svg->substr(start), "<figcaption>plots/", HtmlEscape(file.filename().string()),
                   "</figcaption></figure>\n");
  }
  return html + "</div>\n";
}

}  // namespace

absl::Status WriteHtmlReport(const Json& report, const std::filesystem::path& out_dir) {
  const Json experiments = report.value("experiments", Json::object());
  const Json scenes = ReportPlayerScenes(report, out_dir);
  html_view::Page page;
  page.title = "mocap-eval report";
  page.extra_css = kReportCss;
  page.html_before = StrCat("<h1>mocap-eval report</h1>\n", OtherSections(report), "<h2>Summary</h2>\n",
                            SummaryTable(experiments), PerContentTable(experiments), "<h2>Clips</h2>\n");
  if (scenes.empty()) {
    page.html_before +=
        "<p>No clips to play: the reconstructions and captured clips are written to bvh/ unless "
        "mocap-eval runs with --no-bvh.</p>\n";
  } else {
    page.html_before += StrCat(
        "<p>The full method's reconstruction over the captured motion (colours in the player's legend), for the ",
        kPlayerClipsPerContent,
        " clips of each content type it reconstructed worst (highest "
        "MPJPE first). Choose a clip below the player; drag to orbit, scroll to zoom.</p>\n");
    page.data = {{"layout", "overlay"}, {"scenes", scenes}};
  }
  page.html_after = Plots(out_dir / "plots", experiments);
  return html_view::WriteTextFile(out_dir / "report.html", html_view::PageHtml(page));
}

}  // namespace mocap::eval

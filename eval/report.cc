#include "eval/report.h"

#include <cmath>
#include <fstream>
#include <set>

#include "eval/html_report.h"
#include "eval/svg_chart.h"
#include "motion/core/str_cat.h"

namespace mocap::eval {
namespace {

absl::Status WriteText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) return absl::InternalError(StrCat("cannot write ", path.string()));
  return absl::OkStatus();
}

const ExperimentResult* Find(const std::vector<ExperimentResult>& results, const std::string& name) {
  for (const ExperimentResult& r : results) {
    if (r.experiment.name == name) return &r;
  }
  return nullptr;
}

std::string Fixed(double v, int digits = 2) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.*f", digits, v);
  return buffer;
}

}  // namespace

nlohmann::json MetricsJson(const Metrics& m) {
  const double planted = std::max(1.0, m.planted_frames), jitter_frames = std::max(1.0, m.jitter_frames);
  return {
      {"frames", m.frames},
      {"mpjpe_cm", 100 * m.Mean(m.joint_error_m)},
      {"lower_body_mpjpe_cm", 100 * m.Mean(m.lower_body_error_m)},
      {"pelvis_error_cm", 100 * m.Mean(m.pelvis_error_m)},
      {"ankle_error_cm", 100 * m.Mean(m.ankle_error_m)},
      {"joint_angle_error_deg", m.Mean(m.angle_error_deg)},
      {"joint_angle_rms_deg", std::sqrt(m.Mean(m.angle_error_sq_deg))},
      {"foot_skate_cm_per_frame", 100 * m.skate_m / planted},
      {"truth_foot_skate_cm_per_frame", 100 * m.truth_skate_m / planted},
      {"planted_foot_frames", m.planted_frames},
      {"jitter_m_per_s3", m.jitter / jitter_frames},
      {"truth_jitter_m_per_s3", m.truth_jitter / jitter_frames},
      {"frames_per_second", m.seconds > 0 ? m.frames / m.seconds : 0.0},
  };
}

absl::Status WriteReport(const std::filesystem::path& out_dir, const nlohmann::json& context,
                         const std::vector<ExperimentResult>& results) {
  std::filesystem::create_directories(out_dir / "plots");
  nlohmann::json report = context;
  for (const ExperimentResult& r : results) {
    nlohmann::json entry = {{"group", r.experiment.group}, {"x", r.experiment.x}, {"noise_cm", r.experiment.noise_cm},
                            {"overall", MetricsJson(r.overall)}};
    for (const auto& [content, metrics] : r.by_content) entry["by_content"][content] = MetricsJson(metrics);
    for (const ClipResult& c : r.clips) (entry["clips"][c.name] = MetricsJson(c.metrics))["content"] = c.content;
    report["experiments"][r.experiment.name] = entry;
  }
  const ExperimentResult* full = Find(results, "full");
  const ExperimentResult* nn = Find(results, "nearest_neighbour");
  const ExperimentResult* wrists = Find(results, "wrists_only");
  if (full && nn && wrists) {
    const double f = full->overall.Mean(full->overall.joint_error_m), n = nn->overall.Mean(nn->overall.joint_error_m);
    const double fa = std::sqrt(full->overall.Mean(full->overall.angle_error_sq_deg));
    const double wa = std::sqrt(wrists->overall.Mean(wrists->overall.angle_error_sq_deg));
    report["targets"] = {{"mpjpe_reduction_vs_nearest_neighbour", n > 0 ? 1 - f / n : 0.0},
                         {"mpjpe_reduction_target", 0.25},
                         {"joint_angle_rms_reduction_vs_wrists_only", wa > 0 ? 1 - fa / wa : 0.0},
                         {"joint_angle_rms_reduction_target", 0.32}};
  }
  if (absl::Status s = WriteText(out_dir / "report.json", report.dump(2) + "\n"); !s.ok()) return s;

  // Markdown summary.
  std::string md = "# mocap-eval report\n\n";
  md += StrCat("Database: ", context.value("database", std::string("?")), " (", context.value("database_frames", 0), " frames). ",
               "Test clips: ", context.value("test_clips", 0), ", wrists by forward kinematics plus Gaussian noise (seed ",
               context.value("seed", 0), "). Foot contact of the captured motion: ankle slower than 0.2 m/s on the ground plane ",
               "and within 5 cm of the database's planted ankle height.\n\n");
  md += "| run | MPJPE cm | lower body cm | pelvis cm | ankles cm | angle mean ° | angle RMS ° | skate cm/frame (truth) | jitter m/s³ (truth) | frames/s |\n";
  md += "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const ExperimentResult& r : results) {
    const nlohmann::json m = MetricsJson(r.overall);
    md += StrCat("| ", r.experiment.name, " | ", Fixed(m["mpjpe_cm"]), " | ", Fixed(m["lower_body_mpjpe_cm"]), " | ",
                 Fixed(m["pelvis_error_cm"]), " | ", Fixed(m["ankle_error_cm"]), " | ", Fixed(m["joint_angle_error_deg"]), " | ",
                 Fixed(m["joint_angle_rms_deg"]), " | ", Fixed(m["foot_skate_cm_per_frame"]), " (",
                 Fixed(m["truth_foot_skate_cm_per_frame"]), ") | ", Fixed(m["jitter_m_per_s3"], 1), " (",
                 Fixed(m["truth_jitter_m_per_s3"], 1), ") | ", Fixed(m["frames_per_second"], 0), " |\n");
  }
  if (report.contains("targets")) {
    const nlohmann::json& t = report["targets"];
    md += StrCat("\nMPJPE reduction against the nearest-neighbour baseline: ", Fixed(100 * t["mpjpe_reduction_vs_nearest_neighbour"].get<double>(), 1),
                 "% (target ≥ 25%). Joint-angle RMS reduction against the wrists-only pose model: ",
                 Fixed(100 * t["joint_angle_rms_reduction_vs_wrists_only"].get<double>(), 1), "% (patent: 32%).\n");
  }
  // Per content type, main runs.
  std::set<std::string> contents;
  for (const ExperimentResult& r : results) {
    for (const auto& [c, m] : r.by_content) contents.insert(c);
  }
  const std::vector<std::string> categories(contents.begin(), contents.end());
  std::vector<Series> per_content;
  for (const char* name : {"full", "nearest_neighbour", "wrists_only"}) {
    if (const ExperimentResult* r = Find(results, name)) {
      Series s{name, {}};
      md += StrCat("\n", name, " by content (MPJPE cm): ");
      for (const std::string& c : categories) {
        auto it = r->by_content.find(c);
        const double v = it == r->by_content.end() ? 0.0 : 100 * it->second.Mean(it->second.joint_error_m);
        s.values.push_back(v);
        md += StrCat(c, " ", Fixed(v), "; ");
      }
      per_content.push_back(std::move(s));
    }
  }
  md += "\n\nPlots: `plots/error_by_content.svg`";
  if (absl::Status s = WriteText(out_dir / "plots/error_by_content.svg",
                                 BarChartSvg("MPJPE per content type", "MPJPE (cm)", categories, per_content));
      !s.ok()) {
    return s;
  }
  // Ablations: error against the ablated value.
  for (const auto& [group, x_label] : std::vector<std::pair<std::string, std::string>>{
           {"noise", "wrist noise σ (cm)"}, {"lag", "fixed lag D (frames)"}, {"window", "window L (frames)"}}) {
    std::vector<std::pair<double, double>> points;
    for (const ExperimentResult& r : results) {
      if (r.experiment.group == group) points.push_back({r.experiment.x, 100 * r.overall.Mean(r.overall.joint_error_m)});
    }
    if (points.empty()) continue;
    if (full && group == "noise") points.push_back({full->experiment.noise_cm, 100 * full->overall.Mean(full->overall.joint_error_m)});
    std::sort(points.begin(), points.end());
    std::vector<double> x;
    Series s{"full method", {}};
    for (const auto& [px, py] : points) {
      x.push_back(px);
      s.values.push_back(py);
    }
    const std::string file = StrCat("error_vs_", group, ".svg");
    if (absl::Status st = WriteText(out_dir / "plots" / file, LineChartSvg(StrCat("MPJPE vs ", x_label), x_label, "MPJPE (cm)", x, {s}));
        !st.ok()) {
      return st;
    }
    md += StrCat(", `plots/", file, "`");
  }
  md += "\n";
  if (absl::Status s = WriteText(out_dir / "report.md", md); !s.ok()) return s;
  return WriteHtmlReport(report, out_dir);
}

}  // namespace mocap::eval

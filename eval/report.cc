#include "eval/report.h"

#include <cmath>
#include <fstream>
#include <functional>
#include <set>

#include "eval/clip_plausibility.h"
#include "eval/fixed_format.h"
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

}  // namespace

nlohmann::json MetricsJson(const Metrics& m) {
  const double planted = std::max(1.0, m.planted_frames), jitter_frames = std::max(1.0, m.jitter_frames);
  return {
      {"frames", m.frames},
      {"mpjpe_cm", 100 * m.Mean(m.joint_error_m)},
      {"lower_body_mpjpe_cm", 100 * m.Mean(m.lower_body_error_m)},
      {"upper_body_mpjpe_cm", 100 * m.Mean(m.upper_body_error_m)},
      {"pelvis_error_cm", 100 * m.Mean(m.pelvis_error_m)},
      {"ankle_error_cm", 100 * m.Mean(m.ankle_error_m)},
      {"wrist_error_cm", 100 * m.Mean(m.wrist_error_m)},
      {"joint_angle_error_deg", m.Mean(m.angle_error_deg)},
      {"joint_angle_rms_deg", std::sqrt(m.Mean(m.angle_error_sq_deg))},
      {"foot_skate_cm_per_frame", 100 * m.skate_m / planted},
      {"truth_foot_skate_cm_per_frame", 100 * m.truth_skate_m / planted},
      {"planted_foot_frames", m.planted_frames},
      {"jitter_m_per_s3", m.jitter / jitter_frames},
      {"truth_jitter_m_per_s3", m.truth_jitter / jitter_frames},
      {"frames_per_second", m.seconds > 0 ? m.frames / m.seconds : 0.0},
      {"plausibility", PlausibilityJson(m)},
  };
}

absl::Status WriteReport(const std::filesystem::path& out_dir, const nlohmann::json& context,
                         const std::vector<ExperimentResult>& results) {
  std::filesystem::create_directories(out_dir / "plots");
  nlohmann::json report = context;
  for (const ExperimentResult& r : results) {
    nlohmann::json entry = {{"group", r.experiment.group},
                            {"x", r.experiment.x},
                            {"noise_cm", r.experiment.noise_cm},
                            {"overall", MetricsJson(r.overall)}};
    for (const auto& [content, metrics] : r.by_content) entry["by_content"][content] = MetricsJson(metrics);
    for (const ClipResult& c : r.clips) (entry["clips"][c.name] = MetricsJson(c.metrics))["content"] = c.content;
    entry["confidence"] = ConfidenceJson(r.confidence);
    report["experiments"][r.experiment.name] = entry;
  }
  const ExperimentResult* full = Find(results, "full");
  const ExperimentResult* nn = Find(results, "nearest_neighbour");
  const ExperimentResult* average = Find(results, "nearest_average");
  const ExperimentResult* wrists = Find(results, "wrists_only");
  auto mpjpe = [](const Metrics& m) { return m.Mean(m.joint_error_m); };
  // Headline: the full method against the best baseline, overall and per content type.
  std::vector<const ExperimentResult*> baselines;
  for (const ExperimentResult* b : {nn, average, wrists}) {
    if (b) baselines.push_back(b);
  }
  nlohmann::json headline = nlohmann::json::array();
  if (full && !baselines.empty()) {
    auto row = [&](const std::string& content, const Metrics& f,
                   const std::function<const Metrics*(const ExperimentResult&)>& of) {
      const ExperimentResult* best = nullptr;
      double best_error = 0;
      for (const ExperimentResult* b : baselines) {
        const Metrics* m = of(*b);
        if (m && m->frames > 0 && (!best || mpjpe(*m) < best_error)) {
          best = b;
          best_error = mpjpe(*m);
        }
      }
      if (!best) return;
      headline.push_back({{"content", content},
                          {"full_mpjpe_cm", 100 * mpjpe(f)},
                          {"best_baseline", best->experiment.name},
                          {"best_baseline_mpjpe_cm", 100 * best_error},
                          {"ratio", best_error > 0 ? mpjpe(f) / best_error : 0.0}});
    };
    row("all", full->overall, [](const ExperimentResult& r) { return &r.overall; });
    for (const auto& [name, metrics] : full->by_content) {
      const std::string& content = name;  // (clang 14 cannot capture a structured binding)
      row(content, metrics, [&content](const ExperimentResult& r) -> const Metrics* {
        auto it = r.by_content.find(content);
        return it == r.by_content.end() ? nullptr : &it->second;
      });
    }
    report["headline"] = headline;
  }
  if (full && nn && average && wrists) {
    const double f = mpjpe(full->overall), n = mpjpe(nn->overall), a = mpjpe(average->overall);
    const double fa = std::sqrt(full->overall.Mean(full->overall.angle_error_sq_deg));
    const double wa = std::sqrt(wrists->overall.Mean(wrists->overall.angle_error_sq_deg));
    int worse_than_nn = 0;
    for (const auto& [content, metrics] : full->by_content) {
      auto it = nn->by_content.find(content);
      if (it != nn->by_content.end() && mpjpe(metrics) > mpjpe(it->second)) ++worse_than_nn;
    }
    const nlohmann::json fm = MetricsJson(full->overall);
    report["targets"] = {{"mpjpe_over_nearest_neighbour", n > 0 ? f / n : 0.0},
                         {"mpjpe_over_nearest_neighbour_target", 0.75},
                         {"mpjpe_over_nearest_average", a > 0 ? f / a : 0.0},
                         {"mpjpe_over_nearest_average_target", 0.85},
                         {"content_types_worse_than_nearest_neighbour", worse_than_nn},
                         {"wrist_error_cm", fm["wrist_error_cm"]},
                         {"wrist_error_cm_target", 1.0},
                         {"skate_over_truth", fm["foot_skate_cm_per_frame"].get<double>() /
                                                  std::max(1e-9, fm["truth_foot_skate_cm_per_frame"].get<double>())},
                         {"jitter_over_truth", fm["jitter_m_per_s3"].get<double>() /
                                                   std::max(1e-9, fm["truth_jitter_m_per_s3"].get<double>())},
                         {"joint_angle_rms_reduction_vs_wrists_only", wa > 0 ? 1 - fa / wa : 0.0}};
  }
  if (absl::Status s = WriteText(out_dir / "report.json", report.dump(2) + "\n"); !s.ok()) return s;

  // Markdown summary.
  std::string md = "# mocap-eval report\n\n";
  md += StrCat("Database: ", context.value("database", std::string("?")), " (", context.value("database_frames", 0),
               " frames). ", "Test clips: ", context.value("test_clips", 0),
               ", wrists by forward kinematics plus Gaussian noise (seed ", context.value("seed", 0),
               "). Foot contact of the captured motion: ankle slower than 0.2 m/s on the ground plane ",
               "and within 5 cm of the database's planted ankle height.\n\n");
  md +=
      "| run | MPJPE cm | wrists (input fidelity) cm | pelvis cm | ankles cm | lower body cm | upper body cm | angle "
      "RMS ° | skate cm/frame (truth) | jitter m/s³ (truth) | frames/s |\n";
  md += "|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const ExperimentResult& r : results) {
    const nlohmann::json m = MetricsJson(r.overall);
    md += StrCat("| ", r.experiment.name, " | ", Fixed(m["mpjpe_cm"]), " | ", Fixed(m["wrist_error_cm"]), " | ",
                 Fixed(m["pelvis_error_cm"]), " | ", Fixed(m["ankle_error_cm"]), " | ", Fixed(m["lower_body_mpjpe_cm"]),
                 " | ", Fixed(m["upper_body_mpjpe_cm"]), " | ", Fixed(m["joint_angle_rms_deg"]), " | ",
                 Fixed(m["foot_skate_cm_per_frame"]), " (", Fixed(m["truth_foot_skate_cm_per_frame"]), ") | ",
                 Fixed(m["jitter_m_per_s3"], 1), " (", Fixed(m["truth_jitter_m_per_s3"], 1), ") | ",
                 Fixed(m["frames_per_second"], 0), " |\n");
  }
  md += StrCat(
      "\n## Plausibility (no truth needed)\n\nThe database's bodies move at most ",
      Fixed(context.value("database_pelvis_speed_max_m_per_s", 0.0)), " m/s (pelvis; 99th percentile ",
      Fixed(context.value("database_pelvis_speed_p99_m_per_s", 0.0)), ") and accelerate at most ",
      Fixed(context.value("database_pelvis_acceleration_max_m_per_s2", 0.0), 1), " m/s², their ankles at most ",
      Fixed(context.value("database_ankle_speed_max_m_per_s", 0.0)),
      " m/s. Allowed per clip: max(2 × the capture's fastest pelvis, its fastest + 1 m/s); the same for the "
      "ankles (feet). Hands against the smoothed input where it is within the arm's reach; the lower foot "
      "above the planted ankle height.\n\n"
      "| run | pelvis max m/s (capture's) | p99 m/s | accel max m/s² | clips over allowed | worst / allowed | "
      "ankle max m/s (capture's) | feet: clips over allowed | "
      "hand–input p99 cm (max) | hand-frames out of reach | lower foot p99 cm (max) | under floor max cm | "
      "implausible-input frames | guarded frames |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const ExperimentResult& r : results) {
    const nlohmann::json p = MetricsJson(r.overall)["plausibility"];
    md += StrCat("| ", r.experiment.name, " | ", Fixed(p["pelvis_speed_max_m_per_s"]), " (",
                 Fixed(p["capture_pelvis_speed_max_m_per_s"]), ") | ", Fixed(p["pelvis_speed_p99_m_per_s"]), " | ",
                 Fixed(p["pelvis_acceleration_max_m_per_s2"], 1), " | ", p["clips_faster_than_allowed"].get<double>(),
                 " | ", Fixed(p["worst_speed_over_allowed"]), " | ", Fixed(p["ankle_speed_max_m_per_s"]), " (",
                 Fixed(p["capture_ankle_speed_max_m_per_s"]), ") | ", p["clips_feet_faster_than_allowed"].get<double>(),
                 " | ", Fixed(p["hand_to_input_p99_cm"]), " (", Fixed(p["hand_to_input_max_cm"]), ") | ",
                 p["hand_frames_out_of_reach"].get<long>(), " | ", Fixed(p["lower_foot_height_p99_cm"]), " (",
                 Fixed(p["lower_foot_height_max_cm"]), ") | ", Fixed(p["ground_penetration_max_cm"]), " | ",
                 p["implausible_input_frames"].get<long>(), " | ", p["motion_limited_frames"].get<long>(), " |\n");
  }
  if (!headline.empty()) {
    md +=
        "\n## The full method against the best baseline (MPJPE cm)\n\n| content | full | best baseline | its MPJPE | "
        "full / best |\n|---|---|---|---|---|\n";
    for (const nlohmann::json& h : headline) {
      md += StrCat("| ", h["content"].get<std::string>(), " | ", Fixed(h["full_mpjpe_cm"]), " | ",
                   h["best_baseline"].get<std::string>(), " | ", Fixed(h["best_baseline_mpjpe_cm"]), " | ",
                   Fixed(h["ratio"]), h["ratio"].get<double>() > 1.0 ? " (worse)" : "", " |\n");
    }
  }
  if (report.contains("targets")) {
    const nlohmann::json& t = report["targets"];
    md += StrCat("\nTargets: MPJPE / nearest neighbour ", Fixed(t["mpjpe_over_nearest_neighbour"]),
                 " (≤ 0.75); / average of 10 nearest ", Fixed(t["mpjpe_over_nearest_average"]),
                 " (≤ 0.85); content types worse than the nearest neighbour: ",
                 t["content_types_worse_than_nearest_neighbour"].get<int>(), " (0); wrist error ",
                 Fixed(t["wrist_error_cm"]), " cm (≤ 1.0); foot skate ", Fixed(t["skate_over_truth"]), "× and jitter ",
                 Fixed(t["jitter_over_truth"]),
                 "× the capture's (≤ 2×). Joint-angle RMS reduction against the wrists-only pose model: ",
                 Fixed(100 * t["joint_angle_rms_reduction_vs_wrists_only"].get<double>(), 1), "% (patent: 32%).\n");
  }
  md +=
      "\n## Confidence: expected landmark error against actual\n\nEvery frame's expected error of each of the 14 "
      "landmarks (docs/method.md \"Confidence\") against its actual error; bins of equal size by the expected "
      "error. Plot: `plots/confidence_reliability.svg`.\n\n";
  std::vector<std::pair<std::string, const ConfidenceSummary*>> confidence_rows;
  for (const ExperimentResult& r : results) {
    // Calibrated for the full method only (the lookups have no A6 solve to tell from).
    if (r.experiment.options.method == ReconstructionMethod::kFull)
      confidence_rows.emplace_back(r.experiment.name, &r.confidence);
  }
  md += ConfidenceMarkdown(confidence_rows);
  if (full) {
    if (absl::Status s = WriteText(out_dir / "plots/confidence_reliability.svg",
                                   ReliabilitySvg("Expected against actual landmark error (full)", full->confidence));
        !s.ok()) {
      return s;
    }
  }
  // Per content type, main runs.
  std::set<std::string> contents;
  for (const ExperimentResult& r : results) {
    for (const auto& [c, m] : r.by_content) contents.insert(c);
  }
  const std::vector<std::string> categories(contents.begin(), contents.end());
  std::vector<Series> per_content;
  for (const char* name : {"full", "nearest_neighbour", "nearest_average", "wrists_only"}) {
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
      if (r.experiment.group == group)
        points.push_back({r.experiment.x, 100 * r.overall.Mean(r.overall.joint_error_m)});
    }
    if (points.empty()) continue;
    if (full && group == "noise")
      points.push_back({full->experiment.noise_cm, 100 * full->overall.Mean(full->overall.joint_error_m)});
    std::sort(points.begin(), points.end());
    std::vector<double> x;
    Series s{"full method", {}};
    for (const auto& [px, py] : points) {
      x.push_back(px);
      s.values.push_back(py);
    }
    const std::string file = StrCat("error_vs_", group, ".svg");
    if (absl::Status st = WriteText(out_dir / "plots" / file,
                                    LineChartSvg(StrCat("MPJPE vs ", x_label), x_label, "MPJPE (cm)", x, {s}));
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

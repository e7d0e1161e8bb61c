#include "eval/report_player_scenes.h"

#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include "eval/fixed_format.h"
#include "html_view/text_file.h"
#include "html_view/view_clip.h"
#include "motion/core/str_cat.h"

namespace mocap::eval {
namespace {

struct ClipError {
  std::string name;
  double mpjpe_cm = 0;
};

// The per-clip figures of the run whose reconstructions bvh/ holds ("full"), else of the first run
// that has them.
const nlohmann::json* ClipFigures(const nlohmann::json& report) {
  const nlohmann::json* experiments = report.contains("experiments") ? &report["experiments"] : nullptr;
  if (!experiments || !experiments->is_object()) return nullptr;
  if (experiments->contains("full") && (*experiments)["full"].contains("clips"))
    return &(*experiments)["full"]["clips"];
  for (const auto& [name, run] : experiments->items()) {
    if (run.is_object() && run.contains("clips")) return &run["clips"];
  }
  return nullptr;
}

}  // namespace

nlohmann::json ReportPlayerScenes(const nlohmann::json& report, const std::filesystem::path& out_dir,
                                  int clips_per_content) {
  nlohmann::json scenes = nlohmann::json::array();
  const nlohmann::json* figures = ClipFigures(report);
  if (!figures || !figures->is_object()) return scenes;
  std::map<std::string, std::vector<ClipError>> by_content;
  for (const auto& [name, clip] : figures->items()) {
    if (!clip.is_object()) continue;
    const nlohmann::json& mpjpe = clip.contains("mpjpe_cm") ? clip["mpjpe_cm"] : nlohmann::json();
    by_content[clip.value("content", std::string("other"))].push_back(
        {name, mpjpe.is_number() ? mpjpe.get<double>() : 0.0});
  }
  const std::filesystem::path bvh_dir = out_dir / "bvh";
  for (auto& [content, clips] : by_content) {
    std::sort(clips.begin(), clips.end(),
              [](const ClipError& a, const ClipError& b) { return a.mpjpe_cm > b.mpjpe_cm; });
    int taken = 0;
    for (const ClipError& clip : clips) {
      if (taken == clips_per_content) break;
      absl::StatusOr<std::string> reconstruction = html_view::ReadTextFile(bvh_dir / clip.name);
      absl::StatusOr<std::string> truth = html_view::ReadTextFile(bvh_dir / "truth" / clip.name);
      if (!reconstruction.ok() || !truth.ok()) continue;
      scenes.push_back({{"label", StrCat(content, " · ", clip.name, " · MPJPE ", Fixed(clip.mpjpe_cm), " cm")},
                        {"clips",
                         {html_view::ClipJson("reconstruction (full method)", *reconstruction),
                          html_view::ClipJson("captured motion", *truth)}}});
      ++taken;
    }
  }
  return scenes;
}

}  // namespace mocap::eval

#include "client/cli/view_command.h"

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <map>

#include "html_view/text_file.h"
#include "html_view/view_clip.h"
#include "html_view/view_page.h"
#include "motion/core/status_macros.h"

namespace mocap::cli {
namespace {

namespace fs = std::filesystem;

struct ViewOptions {
  std::vector<std::string> inputs;
  std::string output = "view.html";
  std::string layout = "overlay";
  std::string title;
  bool follow = false;
};

// The reconstruction JSON of each BVH: one named on the command line with the same stem, else
// NAME.json beside NAME.bvh when there is one. A JSON that matches no BVH is an error.
absl::StatusOr<std::map<fs::path, fs::path>> PairJsonWithBvh(const std::vector<fs::path>& bvh_files,
                                                             const std::vector<fs::path>& json_files) {
  std::map<fs::path, fs::path> json_of;
  for (const fs::path& json : json_files) {
    auto match =
        std::find_if(bvh_files.begin(), bvh_files.end(), [&](const fs::path& b) { return b.stem() == json.stem(); });
    if (match == bvh_files.end()) {
      return absl::InvalidArgumentError(json.string() +
                                        " matches no BVH given (traces go with the BVH of the same name)");
    }
    json_of[*match] = json;
  }
  for (const fs::path& bvh : bvh_files) {
    fs::path beside = fs::path(bvh).replace_extension(".json");
    if (!json_of.contains(bvh) && fs::is_regular_file(beside)) json_of[bvh] = beside;
  }
  return json_of;
}

// File names, with their folder where two would read the same (a reconstruction beside its capture).
std::vector<std::string> DisplayNames(const std::vector<fs::path>& files) {
  std::vector<std::string> names;
  for (const fs::path& file : files) {
    const bool shared = std::count_if(files.begin(), files.end(),
                                      [&](const fs::path& f) { return f.filename() == file.filename(); }) > 1;
    const fs::path folder = fs::absolute(file).parent_path().filename();
    names.push_back(shared && !folder.empty() ? (folder / file.filename()).string() : file.filename().string());
  }
  return names;
}

absl::StatusOr<nlohmann::json> ReconstructionFromFile(const fs::path& json_path) {
  MOCAP_ASSIGN_OR_RETURN(std::string text, html_view::ReadTextFile(json_path));
  nlohmann::json reconstruction = nlohmann::json::parse(text, nullptr, false);
  if (reconstruction.is_discarded()) return absl::InvalidArgumentError("not JSON");
  return reconstruction;
}

// Adds the traces and expected errors of `json_path` to `clip`; a JSON that cannot be used is
// reported, not fatal.
void AddReconstruction(nlohmann::json& clip, const fs::path& json_path) {
  absl::StatusOr<nlohmann::json> reconstruction = ReconstructionFromFile(json_path);
  absl::StatusOr<nlohmann::json> traces =
      reconstruction.ok() ? html_view::ReconstructionTraces(*reconstruction) : reconstruction.status();
  if (!traces.ok()) {
    spdlog::warn("{}: no traces drawn: {}", json_path.string(), std::string(traces.status().message()));
    return;
  }
  clip["traces"] = std::move(*traces);
  absl::StatusOr<nlohmann::json> confidence = html_view::ReconstructionConfidence(*reconstruction);
  if (confidence.ok()) {
    clip["expectedErrors"] = std::move(*confidence);
  } else {
    spdlog::info("{}: no expected errors drawn: {}", json_path.string(), std::string(confidence.status().message()));
  }
}

int Run(const ViewOptions& o) {
  std::vector<fs::path> bvh_files, json_files;
  for (const std::string& input : o.inputs)
    (fs::path(input).extension() == ".json" ? json_files : bvh_files).emplace_back(input);
  if (bvh_files.empty()) return ReportError(absl::InvalidArgumentError("give at least one BVH file"));
  absl::StatusOr<std::map<fs::path, fs::path>> json_of = PairJsonWithBvh(bvh_files, json_files);
  if (!json_of.ok()) return ReportError(json_of.status());

  nlohmann::json clips = nlohmann::json::array();
  const std::vector<std::string> display_names = DisplayNames(bvh_files);
  std::string names;
  int unreadable = 0;
  for (size_t i = 0; i < bvh_files.size(); ++i) {
    const fs::path& bvh = bvh_files[i];
    absl::StatusOr<std::string> text = html_view::ReadTextFile(bvh);
    if (!text.ok()) return ReportError(text.status());
    nlohmann::json clip = html_view::ClipJson(display_names[i], *text);
    if (const std::string error = html_view::ClipError(clip); !error.empty()) {
      spdlog::error("{} (the page shows this in its place)", error);
      ++unreadable;
    } else if (auto json = json_of->find(bvh); json != json_of->end()) {
      AddReconstruction(clip, json->second);
    }
    names += (names.empty() ? "" : ", ") + display_names[i];
    clips.push_back(std::move(clip));
  }
  html_view::Page page;
  page.title = o.title.empty() ? "mocap view — " + names : o.title;
  page.data = {
      {"layout", o.layout}, {"follow", o.follow}, {"scenes", {{{"label", page.title}, {"clips", std::move(clips)}}}}};
  if (absl::Status s = html_view::WriteTextFile(o.output, html_view::PageHtml(page)); !s.ok()) return ReportError(s);
  std::cout << "wrote " << o.output << " (" << names << ")\n";
  return unreadable == 0 ? 0 : 1;
}

}  // namespace

void RegisterView(CLI::App& app, Registry& registry) {
  auto o = std::make_shared<ViewOptions>();
  CLI::App* command =
      app.add_subcommand("view",
                         "Write one self-contained HTML page playing BVH clips in a browser (no server needed); a "
                         "`mocap reconstruct` JSON given (or beside its BVH) adds wrist and ankle traces and a halo "
                         "around each body landmark as wide as its expected error");
  command->add_option("inputs", o->inputs, "BVH files, and optionally NAME.json beside NAME.bvh")
      ->required()
      ->check(CLI::ExistingFile);
  command->add_option("-o,--output", o->output, "The HTML page to write")->capture_default_str();
  command->add_option("--layout", o->layout, "Clips drawn over each other or in panels side by side")
      ->check(CLI::IsMember({"overlay", "side-by-side"}))
      ->capture_default_str();
  command->add_option("--title", o->title, "The page's title (default: the file names)");
  command->add_flag("--follow", o->follow, "Start with the camera following the bodies (a toggle on the page)");
  registry.AddLocal(command, [o] { return Run(*o); });
}

}  // namespace mocap::cli

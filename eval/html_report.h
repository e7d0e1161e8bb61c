// report.html: mocap-eval's report for a person — the summary tables, the SVG plots inline, and a
// player of the worst reconstructed clips per content type over the captured motion. One
// self-contained file (html_view/), written from report.json's object and the output folder.
#pragma once

#include <filesystem>

#include <nlohmann/json.hpp>

#include "absl/status/status.h"

namespace mocap::eval {

// Reads `report` generically (any runs, splits, content types, metric names) and out_dir/plots/*.svg
// and out_dir/bvh/; writes out_dir/report.html.
absl::Status WriteHtmlReport(const nlohmann::json& report, const std::filesystem::path& out_dir);

}  // namespace mocap::eval

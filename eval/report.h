// mocap-eval's outputs: report.json (every figure), report.md (the summary a person reads) and
// SVG plots (error per content type, error vs noise, error vs latency).
#pragma once

#include <filesystem>
#include <vector>

#include <nlohmann/json.hpp>

#include "absl/status/status.h"
#include "eval/evaluation.h"

namespace mocap::eval {

nlohmann::json MetricsJson(const Metrics& m);
// `context`: what was run (split, sizes, parameters); merged into report.json.
absl::Status WriteReport(const std::filesystem::path& out_dir, const nlohmann::json& context,
                         const std::vector<ExperimentResult>& results);

}  // namespace mocap::eval

// mocap-eval's landmark report (tests on any rig, the cross-dataset protocol): landmarks.json
// (every figure, per run, source, content and clip) and landmarks.md (per source and content:
// the full method against the nearest neighbour and the 10-average, wrist error, plausibility).
#pragma once

#include <filesystem>
#include <vector>

#include <nlohmann/json.hpp>

#include "absl/status/statusor.h"
#include "eval/cross_dataset.h"

namespace mocap::eval {

nlohmann::json LandmarkMetricsJson(const LandmarkMetrics& m, bool accuracy_measured = true);
// `context`: what was run; `left_out`: test files not scored and why. Returns the summary (the
// per-source and device tables of landmarks.md).
absl::StatusOr<std::string> WriteLandmarkReport(const std::filesystem::path& out_dir, const nlohmann::json& context,
                                                const std::vector<std::string>& left_out,
                                                const std::vector<LandmarkExperimentResult>& results);

}  // namespace mocap::eval

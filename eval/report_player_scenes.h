// The clips report.html plays: for each content type, the few test clips the full method
// reconstructed worst (by MPJPE in report.json's per-clip figures), each as the reconstruction
// (bvh/NAME) over the captured motion (bvh/truth/NAME).
#pragma once

#include <filesystem>

#include <nlohmann/json.hpp>

namespace mocap::eval {

inline constexpr int kPlayerClipsPerContent = 3;

// Player scenes ({"label", "clips": [reconstruction, captured]}), content types in name order,
// worst clip first within each. Clips without both BVH files are left out; none: an empty array.
nlohmann::json ReportPlayerScenes(const nlohmann::json& report, const std::filesystem::path& out_dir,
                                  int clips_per_content = kPlayerClipsPerContent);

}  // namespace mocap::eval

// `mocapd inspect FILE.bvh [--json]`: what the importer understands about a file's skeleton.
#pragma once

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "absl/status/statusor.h"
#include "motion/core/units.h"

namespace mocap {

struct InspectOptions {
  std::optional<LengthUnit> unit;  // override unit detection
};

// Reads and analyses one BVH file; the JSON holds groups, landmarks, up axis, units, rate, frames.
absl::StatusOr<nlohmann::json> InspectBvhFile(const std::string& path, const InspectOptions& options);

// Human-readable rendering of InspectBvhFile's JSON.
std::string FormatInspection(const nlohmann::json& report);

}  // namespace mocap

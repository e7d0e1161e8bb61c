// The page data of one clip: its BVH text, and what the player needs to draw it standing on the
// ground in metres — the length unit, the rotation making its up axis +Y, the pelvis and head
// joints — from the importer's own body analysis (motion/skeleton/body_topology.h). Also the
// traces of a `mocap reconstruct` JSON output (smoothed wrist inputs, estimated ankles).
#pragma once

#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "absl/status/statusor.h"

namespace mocap::html_view {

// {"name", "bvh", "note", "metresPerUnit", "toYUp": [x, y, z, w], "pelvis", "head", "landmarks": [the
// joint name of each body landmark, kBodyLandmarkNames order; "" where the analysis found none]}. A text that does
// not parse gives {"name", "bvh", "error": "NAME:LINE: what was expected"}, which the page shows in
// place of the clip; a rig the analysis does not recognise leaves the unit and up axis to the page.
nlohmann::json ClipJson(std::string_view name, std::string_view bvh_text);

// The clip's parse error, if any (the "error" member of ClipJson).
inline std::string ClipError(const nlohmann::json& clip) { return clip.value("error", std::string()); }

// [{"label", "kind": "wrist" | "ankle", "points": [x, y, z, ...]}] (metres, Y up, one point per
// frame of the BVH beside it) from the JSON `mocap reconstruct` writes (its "frames": left_wrist,
// right_wrist, left_ankle, right_ankle). The BVH plays on the input's clock with a dropout too
// long to bridge filled (motion/core/frame_clock.h), the JSON has only the frames made: placed by
// their times at the session's frame rate, the traces go straight across a filled dropout.
// InvalidArgument when it holds no frames.
absl::StatusOr<nlohmann::json> ReconstructionTraces(const nlohmann::json& reconstruction);

// Every frame's expected landmark errors (metres, 14 per frame in kBodyLandmarkNames order,
// flattened; frames placed as the traces are, a filled dropout's 0: unknown) from the JSON
// `mocap reconstruct` writes (its frames' "expected_error").
// InvalidArgument when it holds no frames; NotFound when no frame has them.
absl::StatusOr<nlohmann::json> ReconstructionConfidence(const nlohmann::json& reconstruction);

}  // namespace mocap::html_view

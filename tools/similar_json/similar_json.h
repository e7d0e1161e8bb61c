// The JSON of a similar-pose search, printed by `mocapd similar --json` (local store) and
// `mocap similar --json` (over the SDK): one format from one function, so the two agree.
#pragma once

#include <ostream>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "absl/status/statusor.h"
#include "mocap/v1/pose_search.pb.h"

namespace mocap {

// {"query": QUERY, "window": W, "exact": E, "results": [{"query_frame": F, "matches": [{"database",
//  "clip_id", "file", "frame", "database_frame", "distance", "group_distances": {"spine", ...},
//  "alignment": {"yaw_degrees", "x_body_scales", "z_body_scales"}}]}]}.
// `query` is the BVH file as named on the command line, or "pose".
nlohmann::json SimilarResultsJson(const std::string& query, const v1::FindSimilarPosesResponse& response);

// `--frames A:B` (inclusive) or `A`. InvalidArgument otherwise.
absl::StatusOr<std::pair<int, int>> ParseFrameRange(const std::string& text);

// The same results as text: per query frame, one line per match (distance, database/file, frame).
void PrintSimilarText(const nlohmann::json& results, std::ostream& out);

// A pose file of `--query-pose`: {"up": "+Y", "joints": [{"name": "Hips", "parent": null,
// "position": [x, y, z]}, ...], "landmarks": {"pelvis": "Hips", "head": ..., "left_wrist": ...,
// "right_wrist": ..., "left_ankle": ..., "right_ankle": ...}} (parents listed before children,
// any unit). InvalidArgument naming what is missing or malformed.
absl::StatusOr<v1::NamedPose> NamedPoseFromJson(const nlohmann::json& pose);

// Appends the results of `part` (a part of a streamed answer) to `into`.
void AppendSimilarResults(const v1::FindSimilarPosesResponse& part, v1::FindSimilarPosesResponse* into);

}  // namespace mocap

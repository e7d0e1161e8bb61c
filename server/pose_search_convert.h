// PoseSearch (proto/mocap/v1/pose_search.proto) <-> the similar-pose search (server/similar_search.h):
// request checks with the service's limits, the query, and the matches of a query frame.
#pragma once

#include <optional>
#include <vector>

#include "absl/status/statusor.h"
#include "mocap/v1/pose_search.pb.h"
#include "server/named_pose_convert.h"
#include "server/similar_search.h"

namespace mocap {

// What one call may ask for (pose_search.proto documents them); exceeding one is INVALID_ARGUMENT
// naming the field and the limit.
struct PoseSearchLimits {
  int max_databases = 8;
  int max_top_k = 100;
  int max_query_frames = 2'000;           // FindSimilarPoses
  int max_stream_query_frames = 100'000;  // StreamSimilarPoses
  int max_exact_query_frames = 200;       // with `exact`, either form
  int max_poses = 1'000;
  int max_matches = 20'000;  // query frames x top_k of FindSimilarPoses (its reply's size)
};

// The search options of a request (defaults filled in), after checking every field that needs
// no parsing: databases, top_k, window, weights, suppression, the query's presence and counts.
absl::StatusOr<PoseSearchOptions> SearchOptionsFromProto(const v1::FindSimilarPosesRequest& request,
                                                         const PoseSearchLimits& limits);

// The body point options of a request (scaling, sampling; defaults filled in). INVALID_ARGUMENT
// for a value this server does not know.
absl::StatusOr<BodyPointOptions> PointOptionsFromProto(const v1::FindSimilarPosesRequest& request);

// Parses the query (BVH text or poses) and checks the number of query frames against the limit
// of the call's form (`streaming`).
absl::StatusOr<SimilarQuery> QueryFromProto(const v1::FindSimilarPosesRequest& request,
                                            const PoseSearchOptions& options, const PoseSearchLimits& limits,
                                            bool streaming, const BodyPointOptions& points);

// One query frame's matches.
// `novelty` (MatchNovelty) sets novelty and no_similar_pose.
void ToProto(int query_frame, const std::vector<FoundPose>& matches, std::optional<float> novelty,
             v1::QueryFrameMatches* out);

}  // namespace mocap

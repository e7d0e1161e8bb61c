// libFuzzer target: a pose search request (FindSimilarPoses and StreamSimilarPoses take the same
// message) as the service handles it, minus the transport and the store: the bytes are a
// FindSimilarPosesRequest; its options, body point options and query (a BVH text or named poses)
// are checked with the service's limits, the query is prepared for two synthetic walks' database,
// and its first query frames are searched, with their novelty, and converted back to the reply.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <map>
#include <tuple>

#include "mocap/v1/pose_search.pb.h"
#include "motion/preprocess/clip_preprocessor.h"
#include "motion/skeleton/forward_kinematics.h"
#include "server/pose_search_convert.h"
#include "tests/support/synthetic_clip.h"

namespace {

// The search database of two synthetic walks (straight, and round a circle) under `points`, built
// once per distinct body point options the fuzzer reaches.
mocap::SearchDatabasePtr DatabaseFor(const mocap::BodyPointOptions& points) {
  static auto* cache = new std::map<std::tuple<int, int, int>, mocap::SearchDatabasePtr>;
  const std::tuple<int, int, int> key = {points.points_per_group, static_cast<int>(points.sampling),
                                         static_cast<int>(points.scaling)};
  if (auto it = cache->find(key); it != cache->end()) return it->second;
  auto database = std::make_shared<mocap::SearchDatabase>();
  // No name: only a store makes a database's ref, and the reply's database name is not fuzzed.
  database->summary.frame_rate = 30;
  database->index = mocap::PoseIndex(points);
  int id = 1;
  for (const auto path : {mocap::testing::SyntheticPath::kStraight, mocap::testing::SyntheticPath::kCircle}) {
    const mocap::BvhClip clip = mocap::testing::MakeWalkingClip({.path = path}, 60);
    const mocap::RigModel rig = *mocap::BuildRigModel(clip, {});
    const mocap::PreparedClip prepared = *mocap::PrepareClip(clip, rig, {.frame_rate = 30});
    mocap::ClipPoints clip_points = mocap::MakeClipPoints(mocap::ForwardKinematics(prepared.skeleton, prepared.motion),
                                                          mocap::MakeBodyChains(rig.skeleton, rig.topology), points);
    // The summary of each clip the index holds, in its order (what the store would list).
    database->clips.push_back({.id = id,
                               .source_name = path == mocap::testing::SyntheticPath::kStraight ? "walk" : "circle",
                               .num_frames = static_cast<int>(clip_points.points.rows()),
                               .source_frame_rate = 30,
                               .source_frames = clip.num_frames()});
    clip_points.name = database->clips.back().source_name;
    clip_points.clip_id = id++;
    database->index.AddClip(std::move(clip_points));
  }
  if (!database->index.Build().ok()) __builtin_trap();
  return (*cache)[key] = std::move(database);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  mocap::v1::FindSimilarPosesRequest request;
  if (!request.ParseFromArray(data, static_cast<int>(size))) return 0;
  const mocap::PoseSearchLimits limits;
  absl::StatusOr<mocap::PoseSearchOptions> options = mocap::SearchOptionsFromProto(request, limits);
  if (!options.ok()) return 0;
  absl::StatusOr<mocap::BodyPointOptions> points = mocap::PointOptionsFromProto(request);
  if (!points.ok()) return 0;
  for (const bool streaming : {false, true}) {  // the query's frame limit differs
    absl::StatusOr<mocap::SimilarQuery> query = mocap::QueryFromProto(request, *options, limits, streaming, *points);
    if (!query.ok()) continue;
    if (!query->Prepare({DatabaseFor(*points)}, *points).ok()) continue;
    // Bound the work per input (the service bounds it by its limits and fair scheduling).
    const size_t frames = std::min<size_t>(query->frames().size(), 4);
    for (size_t i = 0; i < frames; ++i) {
      absl::StatusOr<std::vector<mocap::FoundPose>> found = query->Search(i, *options);
      if (!found.ok()) break;
      mocap::v1::QueryFrameMatches reply;
      mocap::ToProto(query->frames()[i], *found, mocap::MatchNovelty(*found, *options), &reply);
    }
  }
  return 0;
}

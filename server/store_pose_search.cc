#include "server/store_pose_search.h"

#include "motion/core/status_macros.h"
#include "server/pose_search_convert.h"
#include "server/similar_search.h"
#include "storage/motion_store.h"
#include "storage/tenant_directory.h"

namespace mocap {

absl::StatusOr<v1::FindSimilarPosesResponse> FindSimilarPosesInStore(const SimilarOptions& options) {
  if (options.databases.empty()) return absl::InvalidArgumentError("name at least one database");
  if (options.frame_step < 1) return absl::InvalidArgumentError("frame step must be at least 1");
  if (options.pose && options.search.window != 1) {
    return absl::InvalidArgumentError("a single pose has no window: use --window 1");
  }
  MOCAP_ASSIGN_OR_RETURN(std::unique_ptr<MotionStore> store,
                         MotionStore::Open(options.store, StoreOpenOptions{.create_if_missing = false}));
  MOCAP_ASSIGN_OR_RETURN(const TenantId tenant, ResolveTenant(*store, options.tenant));
  absl::StatusOr<SimilarQuery> query = [&]() -> absl::StatusOr<SimilarQuery> {
    if (options.pose) {
      return SimilarQuery::FromPoses({FromProto(*options.pose)}, options.points);
    }
    MOCAP_ASSIGN_OR_RETURN(BvhClip clip, ReadBvhFile(options.query));
    return SimilarQuery::FromBvh(std::move(clip), options.query.string(), options.first_frame, options.last_frame,
                                 options.frame_step);
  }();
  if (!query.ok()) return query.status();

  std::vector<SearchDatabasePtr> databases;
  for (const std::string& name : options.databases) {
    MOCAP_ASSIGN_OR_RETURN(DatabaseSummary summary, store->FindDatabase(name, tenant));
    MOCAP_ASSIGN_OR_RETURN(SearchDatabasePtr database, LoadSearchDatabase(*store, summary, options.points));
    databases.push_back(std::move(database));
  }
  MOCAP_RETURN_IF_ERROR(query->Prepare(databases, options.points));
  v1::FindSimilarPosesResponse response;
  response.set_window(options.search.window);
  response.set_exact(options.search.exact);
  for (size_t i = 0; i < query->frames().size(); ++i) {
    MOCAP_ASSIGN_OR_RETURN(std::vector<FoundPose> found, query->Search(i, options.search));
    ToProto(query->frames()[i], found, MatchNovelty(found, options.search), response.add_results());
  }
  return response;
}

}  // namespace mocap

// PoseSearchCall: what both PoseSearch RPCs do before and while searching. On a worker: the
// call's scope (key, admission), every request check and the query's parsing (no search work
// before the request is known good), the tenant's databases (NOT_FOUND for another tenant's);
// then each database's pose index from the registry (built once per version); then the search
// itself on the fair compute pool under the caller's tenant in slices of at most kSliceTime of
// comparisons (the fair pool charges a tenant what its slices cost: issue #24), so neither a
// long query nor one exact window-61 frame (seconds on a large database) holds a compute thread,
// and a cancelled call stops within one slice. Each database's novelty yardstick
// (PoseIndex::NeighbourReference: 256 searches) is measured in the same slices, first.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "mocap/v1/pose_search.pb.h"
#include "server/pose_search_convert.h"
#include "server/service_context.h"
#include "server/similar_search.h"
#include "server/version_registry.h"

namespace mocap {

// What the PoseSearch handlers share.
struct PoseSearchState {
  PoseSearchState(ServiceContext& service, WorkPool& compute, int max_cached_indexes, const PoseSearchLimits& limits);
  ServiceContext& service;
  WorkPool& compute;  // shared with reconstruction sessions (one thread per core)
  const PoseSearchLimits limits;
  // Pose index per database version and point options (DatabaseVersion::variant: PointsVariant).
  TypedVersionRegistry<SearchDatabase> indexes;
};

// The registry variant of a pose index built with `points` ("bone-directions resample"), and back.
std::string PointsVariant(const BodyPointOptions& points);
absl::StatusOr<BodyPointOptions> PointsOfVariant(const std::string& variant);

class PoseSearchCall {
 public:
  virtual ~PoseSearchCall() = default;

 protected:
  PoseSearchCall(PoseSearchState& state, grpc::CallbackServerContext* context, const char* method,
                 const v1::FindSimilarPosesRequest& request, bool streaming);

  // Posts the checks and lookups to a worker; then Searchable() runs on the compute pool.
  void Start();
  // The query is ready: search with SearchSlice, each slice in its own Post().
  virtual void Searchable() = 0;
  // Ends the call with `status` (once; from any pool thread).
  virtual void Complete(absl::Status status) = 0;

  // Searches for up to kSliceTime: the query frames finished meanwhile go into `out` (none when
  // the slice ends inside a frame's search or a yardstick's).
  absl::Status SearchSlice(v1::FindSimilarPosesResponse* out);
  bool done() const { return next_ >= query_->frames().size(); }
  // Runs `task` on the compute pool under the caller's tenant; an exception ends the call INTERNAL.
  void Post(std::function<void()> task);
  void Cancel() { cancelled_ = true; }
  absl::Status CheckCancelled() const;
  grpc::Status End(const absl::Status& status) { return call_.End(status); }

 private:
  static constexpr std::chrono::microseconds kSliceTime{5000};
  static constexpr std::int64_t kRowsPerStep = 32;  // comparisons between looks at the clock

  void Begin();
  void AcquireIndex(size_t index);
  // Starts measuring the yardsticks the databases do not have yet.
  void StartReferences();

  PoseSearchState& state_;
  CallScope call_;
  const v1::FindSimilarPosesRequest& request_;
  const bool streaming_;
  std::atomic<bool> cancelled_{false};
  WorkPool::Key pool_key_ = WorkPool::kSharedKey;
  PoseSearchOptions options_;
  BodyPointOptions points_;
  std::optional<SimilarQuery> query_;
  std::vector<DatabaseVersion> versions_;
  std::vector<SearchDatabasePtr> databases_;
  // Tasks run one after another, so no lock guards what follows.
  std::vector<PoseIndex::ReferenceRun> references_;  // yardsticks still to measure
  size_t next_reference_ = 0;
  std::optional<SimilarSearchRun> run_;  // the search of query frame next_, when started
  size_t next_ = 0;                      // next query frame
};

}  // namespace mocap

#include "server/pose_search_call.h"

#include <algorithm>
#include <exception>

#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"
#include "server/work_pool.h"

namespace mocap {

std::string PointsVariant(const BodyPointOptions& points) {
  return StrCat(ChainScalingName(points.scaling), " ", PointSamplingName(points.sampling));
}

absl::StatusOr<BodyPointOptions> PointsOfVariant(const std::string& variant) {
  const size_t space = variant.find(' ');
  const std::optional<ChainScaling> scaling = ParseChainScaling(variant.substr(0, space));
  const std::optional<PointSampling> sampling =
      space == std::string::npos ? std::nullopt : ParsePointSampling(variant.substr(space + 1));
  if (!scaling || !sampling) return absl::InternalError(StrCat("pose index variant '", variant, "' is not known"));
  return BodyPointOptions{.sampling = *sampling, .scaling = *scaling};
}

PoseSearchState::PoseSearchState(ServiceContext& service_context, WorkPool& compute_pool, int max_cached_indexes,
                                 const PoseSearchLimits& limits_in)
    : service(service_context),
      compute(compute_pool),
      limits(limits_in),
      indexes(service_context.stores, max_cached_indexes, "pose index",
              [](MotionStore& store, const DatabaseVersion& version) -> absl::StatusOr<SearchDatabasePtr> {
                MOCAP_ASSIGN_OR_RETURN(const BodyPointOptions points, PointsOfVariant(version.variant));
                DatabaseSummary summary;
                summary.ref = version.database;
                summary.frame_rate = version.frame_rate;
                return LoadSearchDatabase(store, summary, points);
              }) {}

PoseSearchCall::PoseSearchCall(PoseSearchState& state, grpc::CallbackServerContext* context, const char* method,
                               const v1::FindSimilarPosesRequest& request, bool streaming)
    : state_(state), call_(state.service, context, method), request_(request), streaming_(streaming) {}

void PoseSearchCall::Start() {
  state_.service.workers.Post([this] {
    try {
      Begin();
    } catch (const std::exception& error) {
      Complete(absl::InternalError(StrCat("pose search: ", error.what())));
    }
  });
}

void PoseSearchCall::Begin() {
  absl::Status status = [&]() -> absl::Status {
    MOCAP_RETURN_IF_ERROR(call_.Begin());
    pool_key_ = static_cast<WorkPool::Key>(call_.tenant().id) + 1;  // 0 is the pool's shared key
    MOCAP_ASSIGN_OR_RETURN(options_, SearchOptionsFromProto(request_, state_.limits));
    MOCAP_ASSIGN_OR_RETURN(points_, PointOptionsFromProto(request_));
    MOCAP_ASSIGN_OR_RETURN(SimilarQuery query, QueryFromProto(request_, options_, state_.limits, streaming_, points_));
    query_ = std::move(query);
    for (const std::string& name : request_.databases()) {
      // Another tenant's database answers NotFound exactly like a missing one.
      MOCAP_ASSIGN_OR_RETURN(DatabaseSummary summary, call_.store().FindDatabase(name, call_.tenant().id));
      if (!summary.has_rig || summary.num_clips == 0) {
        return absl::FailedPreconditionError(StrCat("database '", name, "' has no clips: import motion into it first"));
      }
      MOCAP_ASSIGN_OR_RETURN(std::string stamp, call_.store().ContentStamp(summary.ref));
      versions_.push_back({summary.ref, std::move(stamp), summary.frame_rate, PointsVariant(points_)});
    }
    return absl::OkStatus();
  }();
  call_.ReleaseStore();  // searches do not need the store
  if (!status.ok()) return Complete(status);
  databases_.resize(versions_.size());
  AcquireIndex(0);
}

void PoseSearchCall::AcquireIndex(size_t index) {
  if (index == versions_.size()) {
    return Post([this] {
      if (absl::Status status = query_->Prepare(databases_, points_); !status.ok()) return Complete(status);
      StartReferences();
      Searchable();
    });
  }
  // The callback runs at once, or on the builder thread once the index is built.
  state_.indexes.Acquire(versions_[index], [this, index](absl::StatusOr<SearchDatabasePtr> database) {
    if (!database.ok()) return Complete(database.status());
    databases_[index] = std::move(*database);
    AcquireIndex(index + 1);
  });
}

void PoseSearchCall::Post(std::function<void()> task) {
  state_.compute.Post(pool_key_, [this, task = std::move(task)] {
    try {
      task();
    } catch (const std::exception& error) {
      Complete(absl::InternalError(StrCat("pose search: ", error.what())));
    }
  });
}

absl::Status PoseSearchCall::CheckCancelled() const {
  if (cancelled_) return absl::CancelledError("the client went away or its deadline passed");
  return absl::OkStatus();
}

void PoseSearchCall::StartReferences() {
  for (const SearchDatabasePtr& database : databases_) {
    if (database->index.CachedNeighbourReference(options_)) continue;
    // A database of one clip has no yardstick: its matches get no novelty (MatchNovelty).
    absl::StatusOr<PoseIndex::ReferenceRun> reference = database->index.StartNeighbourReference(options_);
    if (reference.ok()) references_.push_back(std::move(*reference));
  }
}

absl::Status PoseSearchCall::SearchSlice(v1::FindSimilarPosesResponse* out) {
  MOCAP_RETURN_IF_ERROR(CheckCancelled());
  const auto deadline = std::chrono::steady_clock::now() + kSliceTime;
  // Over at the slice's time, or sooner when another tenant's work waits for the thread.
  const auto spent = [&] { return std::chrono::steady_clock::now() >= deadline || WorkPool::AnotherKeyWaits(); };
  out->set_window(options_.window);
  out->set_exact(options_.exact);
  for (; next_reference_ < references_.size(); ++next_reference_) {
    PoseIndex::ReferenceRun& reference = references_[next_reference_];
    while (!reference.Step(kRowsPerStep)) {
      if (spent()) return absl::OkStatus();
    }
    (void)reference.Result();  // kept by the index; a database without one gives no novelty
  }
  while (next_ < query_->frames().size()) {
    if (!run_) {
      MOCAP_ASSIGN_OR_RETURN(SimilarSearchRun run, query_->StartSearch(next_, options_));
      run_ = std::move(run);
    }
    while (!run_->Step(kRowsPerStep)) {
      if (spent()) return absl::OkStatus();
    }
    const std::vector<FoundPose> found = run_->Matches();
    run_.reset();
    ToProto(query_->frames()[next_], found, MatchNovelty(found, options_, /*measure=*/false), out->add_results());
    ++next_;
    if (spent()) break;
  }
  return absl::OkStatus();
}

}  // namespace mocap

#include "server/reconstruction_service.h"

#include <random>

#include <spdlog/spdlog.h>

#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"
#include "server/reconstruct_reactor.h"
#include "server/trajectory_reactor.h"

namespace mocap {
namespace {

int ComputeThreads(const ReconstructionLimits& limits) {
  if (limits.compute_threads > 0) return limits.compute_threads;
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

std::string RandomInstanceTag() {
  std::random_device random;
  std::string tag;
  for (int i = 0; i < 6; ++i) tag += "0123456789abcdef"[random() % 16];
  return tag;
}
// Sessions end their slices when another tenant's task waits for a compute thread.
ReconstructionLimits WithSliceYield(ReconstructionLimits limits) {
  limits.session.slice_yield = &WorkPool::AnotherKeyWaits;
  return limits;
}

}  // namespace

std::string ReconstructionState::NextSessionId() { return StrCat(instance_tag, "-s", next_session_id.fetch_add(1)); }

ReconstructionState::ReconstructionState(ServiceContext& service_context, const ReconstructionLimits& limits_in)
    : service(service_context),
      limits(WithSliceYield(limits_in)),
      databases(service_context.stores, limits_in.max_cached_databases, limits_in.time_reversed_copies),
      sessions(limits_in.max_sessions_per_tenant, "reconstruction sessions"),
      streams(limits_in.max_streams > 0 ? limits_in.max_streams
                                        : kDefaultStreamsPerComputeThread * ComputeThreads(limits_in)),
      instance_tag(RandomInstanceTag()),
      pacer(limits_in.message_pacing),
      compute(ComputeThreads(limits_in),
              limits_in.prompt_lane ? WorkPool::PromptLane::kYes : WorkPool::PromptLane::kNo) {}

void AcquireSessionDatabase(ReconstructionState& state, CallScope& call, const std::string& name,
                            std::function<void(absl::StatusOr<ReconstructionDatabases::Database>)> ready) {
  auto answer = [&state, ready](absl::StatusOr<ReconstructionDatabases::Database> result) {
    state.compute.Post([ready, result = std::move(result)] { ready(result); });
  };
  absl::StatusOr<ReconstructionDatabases::Key> key = [&]() -> absl::StatusOr<ReconstructionDatabases::Key> {
    if (name.empty()) return absl::InvalidArgumentError("config.database: name the database to draw motion from");
    MOCAP_ASSIGN_OR_RETURN(DatabaseSummary summary, call.store().FindDatabase(name, call.tenant().id));
    if (!summary.has_rig || summary.num_clips == 0) {
      return absl::FailedPreconditionError(StrCat("database '", name, "' has no clips: import motion into it first"));
    }
    MOCAP_ASSIGN_OR_RETURN(std::string stamp, call.store().ContentStamp(summary.ref));
    return ReconstructionDatabases::Key{summary.ref, std::move(stamp), summary.frame_rate};
  }();
  call.ReleaseStore();  // sessions outlive their need for the store
  if (!key.ok()) return answer(key.status());
  state.databases.Acquire(*key, answer);
}

ReconstructionService::ReconstructionService(ServiceContext& service, const ReconstructionLimits& limits)
    : state_(service, limits), watchdog_([this] { Watch(); }) {}

ReconstructionService::~ReconstructionService() {
  {
    MutexLock lock(&watch_mutex_);
    stopping_ = true;
  }
  watch_wake_.notify_all();
  watchdog_.join();
}

grpc::ServerBidiReactor<grpc::ByteBuffer, grpc::ByteBuffer>* ReconstructionService::Reconstruct(
    grpc::CallbackServerContext* context) {
  return new ReconstructReactor(state_, context);
}

grpc::ServerUnaryReactor* ReconstructionService::ReconstructTrajectory(grpc::CallbackServerContext* context,
                                                                       const grpc::ByteBuffer* request,
                                                                       grpc::ByteBuffer* response) {
  return new TrajectoryReactor(state_, context, request, response);
}

void ReconstructionService::Drain() {
  state_.draining = true;
  MutexLock live(&state_.live_mutex);
  spdlog::info("ending {} reconstruction sessions for shutdown", state_.live.size());
  for (ReconstructReactor* reactor : state_.live) reactor->EndForShutdown();
}

void ReconstructionService::Watch() {
  const auto period =
      std::clamp(state_.limits.idle_timeout / 4, std::chrono::milliseconds(50), std::chrono::milliseconds(1000));
  MutexLock lock(&watch_mutex_);
  while (!watch_mutex_.AwaitFor(watch_wake_, period, [this]() ABSL_NO_THREAD_SAFETY_ANALYSIS { return stopping_; })) {
    const auto cutoff = std::chrono::steady_clock::now() - state_.limits.idle_timeout;
    MutexLock live(&state_.live_mutex);
    for (ReconstructReactor* reactor : state_.live) {
      if (reactor->IdleSince(cutoff)) reactor->EndIdle();
    }
  }
}

}  // namespace mocap

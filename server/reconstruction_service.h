// The Reconstruction gRPC service (proto/mocap/v1/reconstruction.proto) on the callback API.
// Sessions run on a compute pool of one thread per core (no thread per stream); each stream has
// at most one task queued or running, reads its next message only when its replies have been
// written (backpressure), and shares its database's ReconstructionDatabase read-only with every
// other session. A watchdog thread ends sessions idle longer than the limit; Drain ends every
// session at shutdown after sending its remaining frames.
#pragma once

#include <atomic>
#include <chrono>
#include <memory>
#include <set>
#include <thread>

#include "mocap/v1/reconstruction.grpc.pb.h"
#include "motion/core/mutex.h"
#include "server/message_pacer.h"
#include "server/reconstruction_databases.h"
#include "server/service_context.h"
#include "server/session_driver.h"
#include "server/stream_capacity.h"

namespace mocap {

struct ReconstructionLimits {
  int max_sessions_per_tenant = 64;
  int max_streams =
      0;  // live streams on the server, all tenants (0: kDefaultStreamsPerComputeThread per compute thread)
  std::chrono::milliseconds idle_timeout{30000};  // no message from the client for this long
  SessionLimits session;
  int compute_threads = 0;  // 0: one per core
  // One more compute thread, at gRPC's priority, for a quiet tenant's next task (WorkPool's prompt lane).
  bool prompt_lane = true;
  int max_cached_databases = 4;
  // Search the travelling frames also played backwards (DatabaseBuildOptions::time_reversed_copies): bodies
  // walking backwards where the capture only walks forwards, for ~185 more bytes per frame of a
  // database like bandai-namco-2 (4 in 10 of its frames travel).
  bool time_reversed_copies = true;
  // Where several tenants have keys, each tenant's stream messages are read at most this fast
  // (message_pacer.h): a 120 Hz device on every one of a tenant's 64 sessions, one sample a
  // message, is under it; a flood of one-sample messages is slowed to it. 0: not paced; otherwise
  // at least kMinTenantMessageRate, so that no paced read waits longer than 64 ms.
  MessagePacing message_pacing{.messages_per_second = 8000};  // 800 at once
};
inline constexpr double kMinTenantMessageRate = 1000;

class ReconstructReactor;

// What the handlers and every session share.
struct ReconstructionState {
  ReconstructionState(ServiceContext& service, const ReconstructionLimits& limits);
  // A database build still running answers its callers by posting to `compute`, which is
  // destroyed first: the builds end while it is there (found by ThreadSanitizer at shutdown).
  ~ReconstructionState() { databases.WaitForBuilds(); }
  ServiceContext& service;
  const ReconstructionLimits limits;
  ReconstructionDatabases databases;
  TenantAdmission sessions;
  StreamCapacity streams;
  std::atomic<bool> draining{false};
  // Session ids are "<instance>-s<n>": the instance tag is random per process, so replicas behind
  // one load balancer never hand out the same id.
  const std::string instance_tag;
  std::atomic<std::uint64_t> next_session_id{1};
  std::string NextSessionId();
  Mutex live_mutex;
  std::set<ReconstructReactor*> live ABSL_GUARDED_BY(live_mutex);  // streams between start and OnDone
  // Last, so it is destroyed first: its destructor runs the queued tasks and joins its threads,
  // and those tasks use every member above (found by ThreadSanitizer: a task releasing a session's
  // admission while the admissions were being destroyed, at shutdown).
  MessagePacer pacer;
  WorkPool compute;
};

// Reconstruct and ReconstructTrajectory are served raw (ByteBuffer in and out, raw_message.h): their
// messages are parsed and serialized on the compute pool, under the tenant's share, not on gRPC's threads.
class ReconstructionService final
    : public v1::Reconstruction::WithRawCallbackMethod_Reconstruct<
          v1::Reconstruction::WithRawCallbackMethod_ReconstructTrajectory<v1::Reconstruction::Service>> {
 public:
  ReconstructionService(ServiceContext& service, const ReconstructionLimits& limits);
  ~ReconstructionService() override;

  grpc::ServerBidiReactor<grpc::ByteBuffer, grpc::ByteBuffer>* Reconstruct(
      grpc::CallbackServerContext* context) override;
  grpc::ServerUnaryReactor* ReconstructTrajectory(grpc::CallbackServerContext* context, const grpc::ByteBuffer* request,
                                                  grpc::ByteBuffer* response) override;

  // Refuses new sessions (UNAVAILABLE) and ends the live ones: each emits its remaining frames
  // and summary, then ends with UNAVAILABLE so the client reconnects elsewhere.
  void Drain();

  // The compute pool (one thread per core, fair between tenants), shared with PoseSearch.
  WorkPool& compute() { return state_.compute; }

 private:
  void Watch();
  ReconstructionState state_;
  Mutex watch_mutex_;
  std::condition_variable watch_wake_;
  bool stopping_ ABSL_GUARDED_BY(watch_mutex_) = false;
  std::thread watchdog_;
};

// Looks up the tenant's database and acquires its reconstruction database: `ready` gets it (or the
// error) on the compute pool. Used by both RPCs after CallScope::Begin.
void AcquireSessionDatabase(ReconstructionState& state, CallScope& call, const std::string& database,
                            std::function<void(absl::StatusOr<ReconstructionDatabases::Database>)> ready);

}  // namespace mocap

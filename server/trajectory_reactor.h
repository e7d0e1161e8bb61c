// ReconstructTrajectory (the unary form of a reconstruction session): the whole trajectory in one
// request, every frame in one response. Computed like a stream's messages: kSamplesPerTask samples
// per task on the fair compute pool under the caller's tenant, so one large request cannot hold a
// compute thread; a cancelled call (client gone, deadline passed) stops within one frame's work.
// Served raw, as Reconstruct is (raw_message.h): the request is parsed, and the response
// serialized, by compute tasks under the caller's tenant, not on gRPC's threads.
#pragma once

#include <atomic>
#include <memory>
#include <vector>

#include "server/owned_reactor.h"
#include "server/reconstruction_service.h"

namespace mocap {

class TrajectoryReactor : public OwnedReactor<grpc::ServerUnaryReactor> {
 public:
  // Starts the call; the reactor deletes itself when gRPC is done with it.
  TrajectoryReactor(ReconstructionState& state, grpc::CallbackServerContext* context, const grpc::ByteBuffer* request,
                    grpc::ByteBuffer* response);

  void OnCancel() override { cancelled_ = true; }

 private:
  static constexpr int kSamplesPerTask = 8;

  void Begin();
  void Parse() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  void Start(absl::StatusOr<ReconstructionDatabases::Database> database);
  void PostSlice(int begin) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  void Slice(int begin) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  void Complete(absl::Status status) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);

  ReconstructionState& state_;
  CallScope call_;
  const grpc::ByteBuffer* request_bytes_;
  grpc::ByteBuffer* response_bytes_;
  v1::ReconstructTrajectoryRequest request_ ABSL_GUARDED_BY(mutex_);    // parsed by Parse
  v1::ReconstructTrajectoryResponse response_ ABSL_GUARDED_BY(mutex_);  // serialized by Complete
  std::atomic<bool> cancelled_{false};
  WorkPool::Key pool_key_ = WorkPool::kSharedKey;
  // Compute tasks run one after another (each posts the next); each holds mutex_.
  v1::WristSamples samples_ ABSL_GUARDED_BY(mutex_);
  std::unique_ptr<SessionDriver> driver_ ABSL_GUARDED_BY(mutex_);
  std::vector<v1::ReconstructResponse> replies_ ABSL_GUARDED_BY(mutex_);
};

}  // namespace mocap

// What every gRPC handler shares (store connections, workers, limits, counters), and CallScope:
// one call's request id, authentication, admission, log line, counters and status mapping.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include <grpcpp/grpcpp.h>

#include "absl/status/status.h"
#include "server/server_metrics.h"
#include "server/store_pool.h"
#include "server/tenant_admission.h"
#include "server/work_pool.h"
#include "storage/tenant_directory.h"

namespace mocap {

struct ServerLimits {
  int max_message_bytes = 4 << 20;            // any one message, either direction
  int max_calls_per_tenant = 16;              // calls in progress at once
  std::int64_t max_file_bytes = 512ll << 20;  // one imported BVH file
  std::int64_t max_batch_frames = 2'000'000;  // frames an import holds before its batch commits
};

struct ServiceContext {
  StorePool& stores;
  WorkPool& workers;
  TenantAdmission& admission;
  ServerMetrics& metrics;
  ServerLimits limits;
  std::atomic<std::uint64_t> next_request_id{1};
};

// absl codes map 1:1 onto gRPC's. Internal, DataLoss and Unknown details stay in the server log;
// the client gets the request id to quote.
// "OK", "CANCELLED", ...: the code as gRPC documents it, for logs and metrics.
const char* GrpcCodeName(grpc::StatusCode code);

grpc::Status ToGrpcStatus(const absl::Status& status, const std::string& request_id);

class CallScope {
 public:
  CallScope(ServiceContext& service, grpc::CallbackServerContext* context, std::string method);
  ~CallScope();
  CallScope(const CallScope&) = delete;
  CallScope& operator=(const CallScope&) = delete;

  // Leases a store connection, checks the bearer key (Unauthenticated) and admits the call for
  // its tenant (ResourceExhausted) by `admission` (default: the service's calls per tenant).
  // Call once, first.
  // Never throws: a store that fails underneath (an exception from SQLite, an allocation) is an
  // Internal status, so that every reactor that begins with it finishes its call (issue #24).
  absl::Status Begin(TenantAdmission* admission = nullptr, const char* limit_name = "calls_per_tenant");
  // Unauthenticated when the call carries no bearer key at all: checked without the store, so a
  // stream can refuse a keyless client before reading anything. Begin checks it too.
  absl::Status CheckKeyPresent();
  // FailedPrecondition when the server serves a read-only store (call from write RPCs).
  absl::Status RequireWritableStore() const;
  // Returns the store connection early (long calls that no longer need the store).
  void ReleaseStore() { store_.reset(); }
  // Logs the outcome, counts it, releases the connection and admission; the status to finish with.
  grpc::Status End(const absl::Status& status);

  const Tenant& tenant() const { return tenant_; }
  MotionStore& store() { return **store_; }
  ServiceContext& service() { return service_; }
  // Where this call's work counts: the server's counters, and its tenant's once Begin knew it.
  MetricsScope metrics() { return {service_.metrics, tenant_metrics_}; }
  const std::string& request_id() const { return request_id_; }
  grpc::CallbackServerContext* context() { return context_; }

 private:
  absl::Status BeginUnguarded(TenantAdmission* admission, const char* limit_name);
  ServiceContext& service_;
  grpc::CallbackServerContext* context_;
  const std::string method_;
  const std::string request_id_;
  const std::chrono::steady_clock::time_point start_;
  std::optional<StorePool::Lease> store_;
  Tenant tenant_;
  ServerMetrics* tenant_metrics_ = nullptr;
  TenantAdmission::Ticket ticket_;
  bool ended_ = false;
};

}  // namespace mocap

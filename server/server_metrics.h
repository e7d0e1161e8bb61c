// Server-wide counters, and the same counters per tenant, rendered in the Prometheus text format
// (version 0.0.4). ServerStatus.GetMetrics answers a tenant its own and the operator's default
// tenant the server's; only the operator's HTTP endpoint (`mocapd serve --metrics-listen`,
// server/metrics_http.h) shows every tenant's, labelled by name. Thread-safe.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include "motion/core/mutex.h"

namespace mocap {

// A label value as the Prometheus text format writes it between its quotes: backslash, double
// quote and line feed escaped (\\, \", \n).
std::string PrometheusLabelValue(std::string_view value);

class ServerMetrics {
 public:
  void CallStarted() { in_flight_.fetch_add(1); }
  // One finished call: its method, gRPC status code name (e.g. "OK", "NOT_FOUND") and duration.
  void CallFinished(const std::string& method, const std::string& code, double seconds);
  void FilesImported(std::int64_t files, std::int64_t frames) {
    imported_files_.fetch_add(files);
    imported_frames_.fetch_add(frames);
  }
  void BytesReceived(std::int64_t bytes) { received_bytes_.fetch_add(bytes); }
  void BytesSent(std::int64_t bytes) { sent_bytes_.fetch_add(bytes); }
  void Rejected(const std::string& reason);
  // Reconstruction sessions: one started / ended, frames emitted, samples refused, and the
  // server-side time from a sample message's arrival to its frames being ready.
  void SessionStarted() {
    sessions_active_.fetch_add(1);
    sessions_total_.fetch_add(1);
  }
  void SessionEnded() { sessions_active_.fetch_sub(1); }
  void FramesReconstructed(std::int64_t frames) { frames_reconstructed_.fetch_add(frames); }
  void SamplesRejected(std::int64_t samples) { samples_rejected_.fetch_add(samples); }
  // A stream's next read held back by its tenant's message budget (message_pacer.h).
  void ReadPaced() { reads_paced_.fetch_add(1); }
  void ReplyLatency(double seconds);

  // These counters as `mocap_*` series (GetMetrics' answer).
  std::string PrometheusText() const;
  // The operator's view (the metrics HTTP endpoint, never a tenant's key): the server's series as
  // PrometheusText gives them, then the same counters of every tenant that has made a call, as
  // `mocap_tenant_*` series labelled tenant="NAME" (own names, so that a sum over the tenant
  // series never counts a call twice with the server's).
  std::string PrometheusTextWithTenants() const;

  // The counters of one tenant's calls alone: made on first use, kept for the server's life (a
  // tenant's counters must not restart while the server runs). `name` labels them in
  // PrometheusTextWithTenants (tenant names are unique in a store and never change); an empty
  // name keeps the one known.
  ServerMetrics& OfTenant(std::int64_t tenant, std::string_view name = {});

  // Every counter's value at one moment (what the text is rendered from).
  struct Snapshot;

 private:
  struct TenantEntry {
    std::string name;
    std::unique_ptr<ServerMetrics> metrics;
  };
  Snapshot Take() const;

  std::atomic<std::int64_t> in_flight_{0};
  std::atomic<std::int64_t> imported_files_{0};
  std::atomic<std::int64_t> imported_frames_{0};
  std::atomic<std::int64_t> received_bytes_{0};
  std::atomic<std::int64_t> sent_bytes_{0};
  std::atomic<std::int64_t> sessions_active_{0};
  std::atomic<std::int64_t> sessions_total_{0};
  std::atomic<std::int64_t> frames_reconstructed_{0};
  std::atomic<std::int64_t> samples_rejected_{0};
  std::atomic<std::int64_t> reads_paced_{0};
  mutable Mutex mutex_;
  std::map<std::pair<std::string, std::string>, std::int64_t> calls_ ABSL_GUARDED_BY(mutex_);  // (method, code)
  std::map<std::string, double> call_seconds_ ABSL_GUARDED_BY(mutex_);                         // per method
  std::map<std::string, std::int64_t> rejected_ ABSL_GUARDED_BY(mutex_);                       // per reason
  std::array<std::int64_t, 8> latency_buckets_ ABSL_GUARDED_BY(mutex_){};  // ≤ kLatencyBounds[i], then +Inf
  double latency_sum_ ABSL_GUARDED_BY(mutex_) = 0.0;
  std::int64_t latency_count_ ABSL_GUARDED_BY(mutex_) = 0;
  std::map<std::int64_t, TenantEntry> tenants_ ABSL_GUARDED_BY(mutex_);
};

// Where one call's work counts: the server's counters and, once the call's tenant is known, that
// tenant's too.
class MetricsScope {
 public:
  MetricsScope(ServerMetrics& server, ServerMetrics* tenant = nullptr)  // NOLINT: a server's alone
      : server_(&server), tenant_(tenant) {}
  void CallFinished(const std::string& method, const std::string& code, double seconds) {
    Each([&](ServerMetrics& m) { m.CallFinished(method, code, seconds); });
  }
  void FilesImported(std::int64_t files, std::int64_t frames) {
    Each([&](ServerMetrics& m) { m.FilesImported(files, frames); });
  }
  void BytesReceived(std::int64_t bytes) {
    Each([&](ServerMetrics& m) { m.BytesReceived(bytes); });
  }
  void BytesSent(std::int64_t bytes) {
    Each([&](ServerMetrics& m) { m.BytesSent(bytes); });
  }
  void Rejected(const std::string& reason) {
    Each([&](ServerMetrics& m) { m.Rejected(reason); });
  }
  void SessionStarted() {
    Each([](ServerMetrics& m) { m.SessionStarted(); });
  }
  void SessionEnded() {
    Each([](ServerMetrics& m) { m.SessionEnded(); });
  }
  void FramesReconstructed(std::int64_t frames) {
    Each([&](ServerMetrics& m) { m.FramesReconstructed(frames); });
  }
  void ReadPaced() {
    Each([](ServerMetrics& m) { m.ReadPaced(); });
  }
  void SamplesRejected(std::int64_t samples) {
    Each([&](ServerMetrics& m) { m.SamplesRejected(samples); });
  }
  void ReplyLatency(double seconds) {
    Each([&](ServerMetrics& m) { m.ReplyLatency(seconds); });
  }

 private:
  template <typename F>
  void Each(F&& record) {
    record(*server_);
    if (tenant_ != nullptr) record(*tenant_);
  }
  ServerMetrics* server_;
  ServerMetrics* tenant_;
};

}  // namespace mocap

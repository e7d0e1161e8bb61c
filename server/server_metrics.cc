#include "server/server_metrics.h"

#include <sstream>

namespace mocap {
namespace {

// Histogram bounds of the reply latency, seconds (the last bucket is +Inf).
constexpr std::array<double, 7> kLatencyBounds = {0.005, 0.01, 0.02, 0.05, 0.1, 0.25, 1.0};

}  // namespace

void ServerMetrics::ReplyLatency(double seconds) {
  MutexLock lock(&mutex_);
  size_t bucket = 0;
  while (bucket < kLatencyBounds.size() && seconds > kLatencyBounds[bucket]) ++bucket;
  ++latency_buckets_[bucket];
  latency_sum_ += seconds;
  ++latency_count_;
}

void ServerMetrics::CallFinished(const std::string& method, const std::string& code, double seconds) {
  in_flight_.fetch_sub(1);
  MutexLock lock(&mutex_);
  ++calls_[{method, code}];
  call_seconds_[method] += seconds;
}

void ServerMetrics::Rejected(const std::string& reason) {
  MutexLock lock(&mutex_);
  ++rejected_[reason];
}

ServerMetrics& ServerMetrics::OfTenant(std::int64_t tenant) {
  MutexLock lock(&mutex_);
  std::unique_ptr<ServerMetrics>& metrics = tenants_[tenant];
  if (!metrics) metrics = std::make_unique<ServerMetrics>();
  return *metrics;
}

std::string ServerMetrics::PrometheusText() const {
  std::ostringstream out;
  auto gauge = [&](const char* name, const char* type, const char* help, std::int64_t value) {
    out << "# HELP " << name << " " << help << "\n# TYPE " << name << " " << type << "\n"
        << name << " " << value << "\n";
  };
  gauge("mocap_calls_in_flight", "gauge", "Calls being served.", in_flight_.load());
  gauge("mocap_imported_files_total", "counter", "BVH files stored by ImportBvh.", imported_files_.load());
  gauge("mocap_imported_frames_total", "counter", "Frames stored by ImportBvh, at the database rate.",
        imported_frames_.load());
  gauge("mocap_received_bytes_total", "counter", "BVH bytes received by ImportBvh.", received_bytes_.load());
  gauge("mocap_sent_bytes_total", "counter", "BVH bytes sent by ExportClip.", sent_bytes_.load());
  gauge("mocap_sessions_active", "gauge", "Reconstruction sessions in progress.", sessions_active_.load());
  gauge("mocap_sessions_total", "counter", "Reconstruction sessions started.", sessions_total_.load());
  gauge("mocap_frames_reconstructed_total", "counter", "Frames emitted by reconstruction sessions.",
        frames_reconstructed_.load());
  gauge("mocap_samples_rejected_total", "counter",
        "Wrist samples refused (non-finite, time not increasing, low confidence).", samples_rejected_.load());
  MutexLock lock(&mutex_);
  out << "# HELP mocap_reply_latency_seconds Sample message arrival to its frames being ready.\n"
         "# TYPE mocap_reply_latency_seconds histogram\n";
  std::int64_t cumulative = 0;
  for (size_t i = 0; i < latency_buckets_.size(); ++i) {
    cumulative += latency_buckets_[i];
    out << "mocap_reply_latency_seconds_bucket{le=\"";
    if (i < kLatencyBounds.size())
      out << kLatencyBounds[i];
    else
      out << "+Inf";
    out << "\"} " << cumulative << "\n";
  }
  out << "mocap_reply_latency_seconds_sum " << latency_sum_ << "\nmocap_reply_latency_seconds_count " << latency_count_
      << "\n";
  out << "# HELP mocap_calls_total Finished calls by method and status code.\n# TYPE mocap_calls_total counter\n";
  for (const auto& [key, count] : calls_) {
    out << "mocap_calls_total{method=\"" << key.first << "\",code=\"" << key.second << "\"} " << count << "\n";
  }
  out << "# HELP mocap_call_seconds_total Time spent in finished calls by method.\n"
         "# TYPE mocap_call_seconds_total counter\n";
  for (const auto& [method, seconds] : call_seconds_) {
    out << "mocap_call_seconds_total{method=\"" << method << "\"} " << seconds << "\n";
  }
  out << "# HELP mocap_rejected_total Calls refused by a limit, by limit.\n# TYPE mocap_rejected_total counter\n";
  for (const auto& [reason, count] : rejected_)
    out << "mocap_rejected_total{limit=\"" << reason << "\"} " << count << "\n";
  return out.str();
}

}  // namespace mocap

#include "server/server_metrics.h"

#include <charconv>
#include <utility>
#include <vector>

namespace mocap {
namespace {

// Histogram bounds of the reply latency, seconds (the last bucket is +Inf).
constexpr std::array<double, 7> kLatencyBounds = {0.005, 0.01, 0.02, 0.05, 0.1, 0.25, 1.0};

// The shortest text that reads back as the same double (a counter of seconds keeps its precision
// as it grows).
std::string FormatDouble(double value) {
  std::array<char, 32> text;
  const auto [end, error] = std::to_chars(text.data(), text.data() + text.size(), value);
  return error == std::errc() ? std::string(text.data(), end) : "NaN";
}

}  // namespace

std::string PrometheusLabelValue(std::string_view value) {
  std::string out;
  out.reserve(value.size());
  for (const char c : value) {
    switch (c) {
      case '\\':
        out += "\\\\";
        break;
      case '"':
        out += "\\\"";
        break;
      case '\n':
        out += "\\n";
        break;
      default:
        out += c;
    }
  }
  return out;
}

// Every counter's value at one moment, to render.
struct ServerMetrics::Snapshot {
  std::int64_t in_flight = 0;
  std::int64_t imported_files = 0;
  std::int64_t imported_frames = 0;
  std::int64_t received_bytes = 0;
  std::int64_t sent_bytes = 0;
  std::int64_t sessions_active = 0;
  std::int64_t sessions_total = 0;
  std::int64_t frames_reconstructed = 0;
  std::int64_t samples_rejected = 0;
  std::int64_t reads_paced = 0;
  std::map<std::pair<std::string, std::string>, std::int64_t> calls;
  std::map<std::string, double> call_seconds;
  std::map<std::string, std::int64_t> rejected;
  std::array<std::int64_t, 8> latency_buckets{};
  double latency_sum = 0.0;
  std::int64_t latency_count = 0;
};

namespace {

// One set of series to render: its leading labels (`tenant="acme",`, escaped; empty for the
// server's) and its values.
struct Series {
  std::string labels;
  const ServerMetrics::Snapshot* values;
};

// Renders each metric family once (HELP, TYPE, then one sample per set of series), every name
// `prefix` + its suffix ("mocap_" + "calls_total").
class FamilyWriter {
 public:
  FamilyWriter(std::string& out, std::string prefix, std::string help_suffix)
      : out_(out), prefix_(std::move(prefix)), help_suffix_(std::move(help_suffix)) {}

  void Header(const char* suffix, const char* type, const char* help) {
    out_ +=
        "# HELP " + prefix_ + suffix + " " + help + help_suffix_ + "\n# TYPE " + prefix_ + suffix + " " + type + "\n";
  }
  // `leading` and `labels` are both "name=\"value\"," lists (escaped, each ending in a comma).
  void Sample(const char* suffix, const std::string& leading, const std::string& labels, const std::string& value) {
    out_ += prefix_ + suffix;
    std::string all = leading + labels;
    if (!all.empty()) {
      all.pop_back();  // the last comma
      out_ += "{" + all + "}";
    }
    out_ += " " + value + "\n";
  }

 private:
  std::string& out_;
  const std::string prefix_;
  const std::string help_suffix_;
};

std::string Label(const char* name, std::string_view value) {
  return std::string(name) + "=\"" + PrometheusLabelValue(value) + "\",";
}

void Render(std::string& out, const std::string& prefix, const std::string& help_suffix,
            const std::vector<Series>& sets) {
  FamilyWriter writer(out, prefix, help_suffix);
  auto scalar = [&](const char* suffix, const char* type, const char* help,
                    std::int64_t ServerMetrics::Snapshot::*member) {
    writer.Header(suffix, type, help);
    for (const Series& set : sets) writer.Sample(suffix, set.labels, "", std::to_string(set.values->*member));
  };
  using S = ServerMetrics::Snapshot;
  scalar("calls_in_flight", "gauge", "Calls being served.", &S::in_flight);
  scalar("imported_files_total", "counter", "BVH files stored by ImportBvh.", &S::imported_files);
  scalar("imported_frames_total", "counter", "Frames stored by ImportBvh, at the database rate.", &S::imported_frames);
  scalar("received_bytes_total", "counter", "BVH bytes received by ImportBvh.", &S::received_bytes);
  scalar("sent_bytes_total", "counter", "BVH bytes sent by ExportClip.", &S::sent_bytes);
  scalar("sessions_active", "gauge", "Reconstruction sessions in progress.", &S::sessions_active);
  scalar("sessions_total", "counter", "Reconstruction sessions started.", &S::sessions_total);
  scalar("frames_reconstructed_total", "counter", "Frames emitted by reconstruction sessions.",
         &S::frames_reconstructed);
  scalar("samples_rejected_total", "counter",
         "Wrist samples refused (non-finite, time not increasing, low confidence).", &S::samples_rejected);
  scalar("reads_paced_total", "counter",
         "Reconstruction stream reads held back by the message budget of the key's owner (a serve option).",
         &S::reads_paced);

  writer.Header("reply_latency_seconds", "histogram", "Sample message arrival to its frames being ready.");
  for (const Series& set : sets) {
    std::int64_t cumulative = 0;
    for (size_t i = 0; i < set.values->latency_buckets.size(); ++i) {
      cumulative += set.values->latency_buckets[i];
      const std::string bound = i < kLatencyBounds.size() ? FormatDouble(kLatencyBounds[i]) : "+Inf";
      writer.Sample("reply_latency_seconds_bucket", set.labels, Label("le", bound), std::to_string(cumulative));
    }
    writer.Sample("reply_latency_seconds_sum", set.labels, "", FormatDouble(set.values->latency_sum));
    writer.Sample("reply_latency_seconds_count", set.labels, "", std::to_string(set.values->latency_count));
  }

  writer.Header("calls_total", "counter", "Finished calls by method and status code.");
  for (const Series& set : sets) {
    for (const auto& [key, count] : set.values->calls) {
      writer.Sample("calls_total", set.labels, Label("method", key.first) + Label("code", key.second),
                    std::to_string(count));
    }
  }
  writer.Header("call_seconds_total", "counter", "Time spent in finished calls by method.");
  for (const Series& set : sets) {
    for (const auto& [method, seconds] : set.values->call_seconds)
      writer.Sample("call_seconds_total", set.labels, Label("method", method), FormatDouble(seconds));
  }
  writer.Header("rejected_total", "counter", "Calls refused by a limit, by limit.");
  for (const Series& set : sets) {
    for (const auto& [reason, count] : set.values->rejected)
      writer.Sample("rejected_total", set.labels, Label("limit", reason), std::to_string(count));
  }
}

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

ServerMetrics& ServerMetrics::OfTenant(std::int64_t tenant, std::string_view name) {
  MutexLock lock(&mutex_);
  TenantEntry& entry = tenants_[tenant];
  if (!entry.metrics) entry.metrics = std::make_unique<ServerMetrics>();
  if (!name.empty() && entry.name != name) entry.name = std::string(name);
  return *entry.metrics;
}

ServerMetrics::Snapshot ServerMetrics::Take() const {
  Snapshot values;
  values.in_flight = in_flight_.load();
  values.imported_files = imported_files_.load();
  values.imported_frames = imported_frames_.load();
  values.received_bytes = received_bytes_.load();
  values.sent_bytes = sent_bytes_.load();
  values.sessions_active = sessions_active_.load();
  values.sessions_total = sessions_total_.load();
  values.frames_reconstructed = frames_reconstructed_.load();
  values.samples_rejected = samples_rejected_.load();
  values.reads_paced = reads_paced_.load();
  MutexLock lock(&mutex_);
  values.calls = calls_;
  values.call_seconds = call_seconds_;
  values.rejected = rejected_;
  values.latency_buckets = latency_buckets_;
  values.latency_sum = latency_sum_;
  values.latency_count = latency_count_;
  return values;
}

std::string ServerMetrics::PrometheusText() const {
  const Snapshot values = Take();
  std::string out;
  Render(out, "mocap_", "", {{"", &values}});
  return out;
}

std::string ServerMetrics::PrometheusTextWithTenants() const {
  std::string out = PrometheusText();
  // The tenants' counters are never dropped, so their addresses outlive the lock; each is read
  // under its own mutex, never under this one.
  std::map<std::string, const ServerMetrics*> tenants;  // by name: the series in a stable order
  {
    MutexLock lock(&mutex_);
    for (const auto& [id, entry] : tenants_)
      tenants.emplace(entry.name.empty() ? std::to_string(id) : entry.name, entry.metrics.get());
  }
  if (tenants.empty()) return out;
  std::vector<Snapshot> values;
  values.reserve(tenants.size());
  std::vector<Series> sets;
  for (const auto& [name, metrics] : tenants) {
    values.push_back(metrics->Take());
    sets.push_back({Label("tenant", name), &values.back()});
  }
  Render(out, "mocap_tenant_", " By tenant.", sets);
  return out;
}

}  // namespace mocap

#include "client/load/stream_load.h"

#include <algorithm>
#include <mutex>
#include <optional>
#include <thread>

namespace mocap::load {
namespace {

using Clock = std::chrono::steady_clock;

// When each sample was handed to the SDK; read by the reader thread while the writer fills it.
class SendTimes {
 public:
  explicit SendTimes(size_t n) : times_(n) {}
  void Set(size_t i, Clock::time_point t) {
    std::lock_guard lock(mutex_);
    times_[i] = t;
    sent_ = i + 1;
  }
  // The send time of sample i, or nullopt when it has not been sent.
  std::optional<Clock::time_point> Get(size_t i) {
    std::lock_guard lock(mutex_);
    if (i >= sent_) return std::nullopt;
    return times_[i];
  }

 private:
  std::mutex mutex_;
  std::vector<Clock::time_point> times_;
  size_t sent_ = 0;
};

}  // namespace

StreamOutcome RunStream(client::Client& client, const StreamPlan& plan) {
  StreamOutcome outcome;
  std::this_thread::sleep_until(plan.start);
  auto opened = client.OpenReconstruction(plan.config);
  if (!opened.ok()) {
    outcome.status = opened.status();
    return outcome;
  }
  client::ReconstructionStream& stream = **opened;
  const double frame_rate = stream.started().frame_rate();
  const int lag = plan.config.has_fixed_lag() ? plan.config.fixed_lag().lag_frames() : 0;
  const double lag_seconds = frame_rate > 0 ? lag / frame_rate : 0.0;
  SendTimes send_times(plan.samples.size());

  std::thread reader([&] {
    size_t completing = 0;  // first sample at or after the frame's time plus the lag (monotone)
    while (true) {
      auto reply = stream.Read();
      if (!reply.ok() || !*reply) return;
      const Clock::time_point now = Clock::now();
      if ((*reply)->has_rejected()) ++outcome.rejected;
      for (const v1::Frame& frame : (*reply)->frames().frames()) {
        ++outcome.frames;
        const double due = frame.time() + lag_seconds - 1e-6;
        while (completing + 1 < plan.samples.size() && plan.samples[completing].time() < due) ++completing;
        // The last frames of a fixed-lag session are completed by the end of the input, not by a
        // sample: they have no latency to report.
        if (plan.samples.empty() || plan.samples[completing].time() < due) continue;
        if (auto sent = send_times.Get(completing)) {
          outcome.latencies_ms.push_back(std::chrono::duration<double, std::milli>(now - *sent).count());
        }
      }
    }
  });

  const Clock::time_point stream_start = Clock::now();
  const double first_time = plan.samples.empty() ? 0.0 : plan.samples.front().time();
  for (size_t i = 0; i < plan.samples.size(); ++i) {
    const auto due = stream_start + std::chrono::duration_cast<Clock::duration>(
                                        std::chrono::duration<double>(plan.samples[i].time() - first_time));
    std::this_thread::sleep_until(due);
    const Clock::time_point now = Clock::now();
    outcome.late_send_ms = std::max(outcome.late_send_ms, std::chrono::duration<double, std::milli>(now - due).count());
    send_times.Set(i, now);
    if (!stream.Write({plan.samples[i]}).ok()) break;  // the call ended: Finish says why
    ++outcome.samples_sent;
  }
  stream.CloseInput().IgnoreError();  // always OK
  reader.join();
  absl::StatusOr<v1::SessionSummary> summary = stream.Finish();
  outcome.status = summary.status();
  if (summary.ok()) outcome.summary = *summary;
  return outcome;
}

}  // namespace mocap::load

#include "client/load/stream_load.h"

#include <algorithm>
#include <atomic>
#include <condition_variable>
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
  outcome.sessions = 1;
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
          outcome.latency_sent.push_back(*sent);
        }
      }
    }
  });

  const Clock::time_point stream_start = Clock::now();
  const double first_time = plan.samples.empty() ? 0.0 : plan.samples.front().time();
  const size_t per_message = static_cast<size_t>(std::max(1, plan.samples_per_message));
  // Cancel-and-reopen: a timer cancels the call even while a Write waits for the server.
  std::atomic<bool> cancelled = false;
  std::mutex session_mutex;
  std::condition_variable session_over;
  bool over = false;
  std::thread canceller;
  if (plan.cancel_after) {
    canceller = std::thread([&] {
      std::unique_lock lock(session_mutex);
      if (!session_over.wait_for(lock, *plan.cancel_after, [&] { return over; })) {
        cancelled = true;
        stream.Cancel();
      }
    });
  }
  std::vector<v1::WristSample> message;
  for (size_t i = 0; i < plan.samples.size() && !cancelled; i += per_message) {
    if (plan.paced) {
      const auto due = stream_start + std::chrono::duration_cast<Clock::duration>(
                                          std::chrono::duration<double>(plan.samples[i].time() - first_time));
      std::this_thread::sleep_until(due);
      outcome.late_send_ms =
          std::max(outcome.late_send_ms, std::chrono::duration<double, std::milli>(Clock::now() - due).count());
    }
    const size_t end = std::min(plan.samples.size(), i + per_message);
    message.assign(plan.samples.begin() + static_cast<std::ptrdiff_t>(i),
                   plan.samples.begin() + static_cast<std::ptrdiff_t>(end));
    const Clock::time_point now = Clock::now();
    for (size_t j = i; j < end; ++j) send_times.Set(j, now);
    if (!stream.Write(message).ok()) break;  // the call ended: Finish says why
    outcome.samples_sent += static_cast<long>(end - i);
  }
  if (!cancelled) stream.CloseInput().IgnoreError();  // always OK
  reader.join();
  if (canceller.joinable()) {
    {
      std::lock_guard lock(session_mutex);
      over = true;
    }
    session_over.notify_one();
    canceller.join();
  }
  if (cancelled) ++outcome.cancelled;
  absl::StatusOr<v1::SessionSummary> summary = stream.Finish();
  outcome.status = summary.status();
  if (cancelled && absl::IsCancelled(outcome.status)) outcome.status = absl::OkStatus();  // as planned
  if (summary.ok()) outcome.summary = *summary;
  return outcome;
}

void Accumulate(StreamOutcome& total, StreamOutcome one) {
  if (total.status.ok()) total.status = one.status;
  total.latencies_ms.insert(total.latencies_ms.end(), one.latencies_ms.begin(), one.latencies_ms.end());
  total.latency_sent.insert(total.latency_sent.end(), one.latency_sent.begin(), one.latency_sent.end());
  total.samples_sent += one.samples_sent;
  total.frames += one.frames;
  total.rejected += one.rejected;
  total.sessions += one.sessions;
  total.cancelled += one.cancelled;
  total.late_send_ms = std::max(total.late_send_ms, one.late_send_ms);
  if (one.summary.ByteSizeLong() > 0) total.summary = std::move(one.summary);
}

}  // namespace mocap::load

// One simulated tracker for the load generator: a Reconstruct stream fed wrist samples in real
// time (one message per sample at the input rate, as an app sends them), with a reader thread
// timing every frame that comes back. Hostile shapes for fairness benchmarks: several samples per
// message, messages sent as fast as the server takes them, and sessions cancelled and reopened.
//
// A frame's latency is measured from the moment the sample that completed it was handed to the
// SDK to the moment the frame was read: with fixed lag D the frame at time t is complete once the
// first sample at or after t + D / frame rate has arrived, so the window's own lag is excluded and
// what remains is transport, queueing and processing (what the p99 target is about).
#pragma once

#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "mocap/client.h"

namespace mocap::load {

struct StreamPlan {
  v1::SessionConfig config;
  std::vector<v1::WristSample> samples;  // sent in order, each at start + (time − first time)
  std::chrono::steady_clock::time_point start;
  int samples_per_message = 1;  // a message goes when its first sample is due (or at once, unpaced)
  bool paced = true;            // false: every message as soon as the stream accepts it
  // When set, the session is cancelled this long after it opened (Finish: CANCELLED, which the
  // outcome counts as `cancelled`, not as an error).
  std::optional<std::chrono::steady_clock::duration> cancel_after;
};

struct StreamOutcome {
  absl::Status status;               // the session's end (OK, or the server's error)
  std::vector<double> latencies_ms;  // one per frame received
  // When the sample that completed each of those frames was sent (the same order): where in the
  // run the latency was, so a stall can be told from a steady backlog.
  std::vector<std::chrono::steady_clock::time_point> latency_sent;
  long samples_sent = 0;
  long frames = 0;
  long rejected = 0;
  long sessions = 0;           // sessions opened (more than one with cancel-and-reopen)
  long cancelled = 0;          // sessions this side cancelled on purpose
  double late_send_ms = 0;     // worst delay of a send behind its schedule (backpressure)
  v1::SessionSummary summary;  // the server's, when the session ended OK
};

// Runs one session to its end (blocks). Never throws; errors are in the outcome.
StreamOutcome RunStream(client::Client& client, const StreamPlan& plan);

// Adds one session's outcome to a stream's running total (the first error is kept).
void Accumulate(StreamOutcome& total, StreamOutcome one);

}  // namespace mocap::load

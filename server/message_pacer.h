// MessagePacer: each tenant's stream messages read at most so many a second, where several tenants
// share the server (issue #24, "fair shares by cost"). Reading a message costs gRPC's transport
// threads and a hop through the compute pool whatever the message holds, and those threads run at
// the priority of every tenant's replies: a tenant sending 40,000 one-sample messages a second
// took a quarter of a core from the others' live sessions, outside the pool's fair order
// (docs/deployment.md "Sizing", stop 60). Past its budget a tenant's streams start their next read
// later, so HTTP/2 flow control slows its clients rather than the server.
//
// The budget is a generic cell rate (a token bucket kept as one time per tenant): `rate` messages a
// second on average, `burst` of them at once. Thread-safe.
#pragma once

#include <chrono>
#include <cstdint>
#include <unordered_map>

#include "motion/core/mutex.h"

namespace mocap {

struct MessagePacing {
  double messages_per_second = 0;  // per tenant; 0: not paced
  // Messages read at once before the rate applies (at least 1); 0: a tenth of a second's worth.
  double burst = 0;
};

class MessagePacer {
 public:
  using Clock = std::chrono::steady_clock;
  using Key = std::uint64_t;

  explicit MessagePacer(const MessagePacing& pacing);

  // Counts one message read at `now` from a stream of `key`; returns when that stream's next read
  // may start (at or before `now`: at once).
  Clock::time_point Charge(Key key, Clock::time_point now);

  bool enabled() const { return interval_ > Clock::duration::zero(); }
  // Tenants whose budget is remembered (those paced lately; the others are forgotten as it grows).
  size_t tracked_tenants() const;

 private:
  const Clock::duration interval_;   // one message's share of a second
  const Clock::duration tolerance_;  // how far ahead of the rate the burst lets a tenant run
  mutable Mutex mutex_;
  // Per tenant, when its budget has paid for every message read so far (the cell rate's
  // "theoretical arrival time"); a time in the past is a full bucket.
  std::unordered_map<Key, Clock::time_point> paid_until_ ABSL_GUARDED_BY(mutex_);
};

}  // namespace mocap

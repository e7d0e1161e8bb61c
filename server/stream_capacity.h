// StreamCapacity: at most N live reconstruction streams on this server, whoever's they are
// (issue #26). Past what two cores carry, every stream's latency grows to seconds together (40
// real-time streams at 30 Hz: p99 375 ms; 50: 6.2 s, docs/deployment.md "Sizing"), so the excess
// is refused at admission (RESOURCE_EXHAUSTED, saying so) and the admitted streams keep their
// latency. Where several tenants have keys, one tenant may hold at most kTenantShareOfStreams of
// them, so a tenant that opens streams as fast as it can does not lock the others out; a server
// with one tenant gives it all. Thread-safe.
#pragma once

#include <map>
#include <memory>

#include "absl/status/statusor.h"
#include "motion/core/mutex.h"
#include "storage/motion_store.h"

namespace mocap {

// Live streams a compute thread carries by default: on 2 cores with the load generator beside
// them, 30 real-time 30 Hz streams held a p99 of 19-26 ms once A5 solved only the eigenpairs it
// keeps (29, 47 and 83 ms before: 12 per thread then); 40 streams, all admitted, 375 ms.
inline constexpr int kDefaultStreamsPerComputeThread = 15;
// The most of the server's streams one tenant holds (at least one): the rest stay for others.
inline constexpr double kTenantShareOfStreams = 0.75;

class StreamCapacity {
 public:
  explicit StreamCapacity(int max_streams);

  // Holding a ticket counts one live stream; dropping it ends it.
  using Ticket = std::shared_ptr<void>;
  // ResourceExhausted when max_streams streams are live already, or, when `shared` (other tenants
  // have keys), the tenant holds its share.
  absl::StatusOr<Ticket> Admit(TenantId tenant, bool shared = true);

  int live() const;
  int max_streams() const { return max_streams_; }
  int max_per_tenant() const { return max_per_tenant_; }

 private:
  const int max_streams_;
  const int max_per_tenant_;
  mutable Mutex mutex_;
  int live_ ABSL_GUARDED_BY(mutex_) = 0;
  std::map<TenantId, int> per_tenant_ ABSL_GUARDED_BY(mutex_);
};

}  // namespace mocap

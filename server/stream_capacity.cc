#include "server/stream_capacity.h"

#include <algorithm>
#include <cmath>

#include "motion/core/str_cat.h"

namespace mocap {

StreamCapacity::StreamCapacity(int max_streams)
    : max_streams_(max_streams),
      max_per_tenant_(std::max(1, static_cast<int>(std::floor(kTenantShareOfStreams * max_streams)))) {}

absl::StatusOr<StreamCapacity::Ticket> StreamCapacity::Admit(TenantId tenant, bool shared) {
  {
    MutexLock lock(&mutex_);
    if (live_ >= max_streams_) {
      return absl::ResourceExhaustedError(
          StrCat("this server carries ", max_streams_,
                 " live reconstruction streams, the most it serves in real time (mocapd serve --max-streams); retry "
                 "later or connect to another replica"));
    }
    int& held = per_tenant_[tenant];
    if (shared && held >= max_per_tenant_) {
      return absl::ResourceExhaustedError(
          StrCat("this tenant holds ", held, " of this server's ", max_streams_,
                 " live reconstruction streams, the most one tenant may (the rest stay for others; mocapd serve "
                 "--max-streams); retry later or connect to another replica"));
    }
    ++held;
    ++live_;
  }
  return Ticket(nullptr, [this, tenant](void*) {
    MutexLock lock(&mutex_);
    --live_;
    if (--per_tenant_[tenant] == 0) per_tenant_.erase(tenant);
  });
}

int StreamCapacity::live() const {
  MutexLock lock(&mutex_);
  return live_;
}

}  // namespace mocap

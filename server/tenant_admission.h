// TenantAdmission: at most N calls at once per tenant; the rest are refused (RESOURCE_EXHAUSTED)
// rather than queued, so one tenant cannot take every worker. Thread-safe.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <utility>

#include "absl/status/statusor.h"
#include "motion/core/mutex.h"
#include "storage/motion_store.h"

namespace mocap {

class TenantAdmission {
 public:
  // `what` names the counted things in the refusal ("calls", "reconstruction sessions").
  explicit TenantAdmission(int max_calls_per_tenant, std::string what = "calls")
      : max_calls_(max_calls_per_tenant), what_(std::move(what)) {}

  // Holding a ticket counts one call of its tenant; dropping it ends the call.
  using Ticket = std::shared_ptr<void>;
  // ResourceExhausted when the tenant has max_calls_per_tenant calls already.
  absl::StatusOr<Ticket> Admit(TenantId tenant);

 private:
  const int max_calls_;
  const std::string what_;
  Mutex mutex_;
  std::map<TenantId, int> active_ ABSL_GUARDED_BY(mutex_);
};

}  // namespace mocap

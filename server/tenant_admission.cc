#include "server/tenant_admission.h"

#include "motion/core/str_cat.h"

namespace mocap {

absl::StatusOr<TenantAdmission::Ticket> TenantAdmission::Admit(TenantId tenant) {
  {
    MutexLock lock(&mutex_);
    int& active = active_[tenant];
    if (active >= max_calls_) {
      return absl::ResourceExhaustedError(StrCat("this tenant has ", active, " ", what_,
                                                 " in progress, the most allowed (", max_calls_,
                                                 "); retry when one has finished"));
    }
    ++active;
  }
  return Ticket(nullptr, [this, tenant](void*) {
    MutexLock lock(&mutex_);
    if (--active_[tenant] == 0) active_.erase(tenant);
  });
}

}  // namespace mocap

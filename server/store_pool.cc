#include "server/store_pool.h"

#include "motion/core/status_macros.h"

namespace mocap {

absl::StatusOr<std::unique_ptr<StorePool>> StorePool::Open(const std::filesystem::path& path, bool read_only) {
  std::unique_ptr<StorePool> pool(new StorePool(path, read_only));
  MOCAP_ASSIGN_OR_RETURN(std::unique_ptr<MotionStore> first,
                         read_only ? MotionStore::Open(path, pool->Options()) : MotionStore::Open(path));
  {
    MutexLock lock(&pool->mutex_);  // no other thread has the pool yet; the analysis wants it
    pool->idle_.push_back(std::move(first));
  }
  return pool;
}

absl::StatusOr<StorePool::Lease> StorePool::Acquire() {
  std::unique_ptr<MotionStore> store;
  {
    MutexLock lock(&mutex_);
    if (!idle_.empty()) {
      store = std::move(idle_.back());
      idle_.pop_back();
    }
  }
  if (!store) {
    MOCAP_ASSIGN_OR_RETURN(store, MotionStore::Open(path_, Options()));
  }
  return Lease(store.release(), [this](MotionStore* returned) {
    MutexLock lock(&mutex_);
    idle_.emplace_back(returned);
  });
}

}  // namespace mocap

// WorkPool: a fixed set of threads running queued tasks. gRPC callback handlers post their store,
// parsing and compute work here, so no gRPC thread blocks and no call owns a thread while it
// waits for its client.
//
// Fair sharing: every task is posted under a queue key (the reconstruction service uses the
// tenant). Each key has its own FIFO queue and the threads take one task from each non-empty
// queue in turn (round robin), so a key with 64 busy sessions gets no more of the pool than a key
// with one. Long work must therefore be cut into short tasks (a reconstruction runs a few
// samples per task): fairness is per task, not per second.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <thread>
#include <vector>
#include "motion/core/mutex.h"

namespace mocap {

class WorkPool {
 public:
  using Key = std::uint64_t;
  static constexpr Key kSharedKey = 0;  // work not attributed to a tenant (yet)

  explicit WorkPool(int threads);
  // Runs the queued tasks, then joins the threads.
  ~WorkPool();
  WorkPool(const WorkPool&) = delete;
  WorkPool& operator=(const WorkPool&) = delete;

  // Thread-safe. A task that throws is logged and dropped (last resort: callers catch their own).
  void Post(std::function<void()> task) { Post(kSharedKey, std::move(task)); }
  void Post(Key key, std::function<void()> task);

  // Tasks queued and not yet started, over all keys.
  size_t queued() const;

 private:
  void Work();
  bool HasWorkOrStopping() const ABSL_SHARED_LOCKS_REQUIRED(mutex_) { return stopping_ || !turn_.empty(); }
  mutable Mutex mutex_;
  std::condition_variable ready_;  // a task was queued, or the pool is stopping
  std::map<Key, std::deque<std::function<void()>>> queues_ ABSL_GUARDED_BY(mutex_);  // only non-empty queues
  std::deque<Key> turn_ ABSL_GUARDED_BY(mutex_);  // keys with queued tasks, in the order they are served
  size_t queued_ ABSL_GUARDED_BY(mutex_) = 0;
  bool stopping_ ABSL_GUARDED_BY(mutex_) = false;
  std::vector<std::thread> threads_;
};

}  // namespace mocap

#include "server/work_pool.h"

#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <exception>

#include <spdlog/spdlog.h>

namespace mocap {

namespace {

// Pool threads run below gRPC's own threads: reading, writing and answering calls is short work
// that must not queue behind compute, or one tenant's saturating flood delays every other
// tenant's replies in the transport, whatever the pool's fair order (issue #14: the victim's p99).
constexpr int kWorkerNiceness = 5;

void LowerThisThreadsPriority() {
  if (setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), kWorkerNiceness) != 0) {
    spdlog::warn("work pool: cannot lower a worker's priority: {}", std::strerror(errno));
  }
}

}  // namespace

WorkPool::WorkPool(int threads) {
  for (int i = 0; i < threads; ++i) {
    threads_.emplace_back([this] {
      LowerThisThreadsPriority();
      Work();
    });
  }
}

WorkPool::~WorkPool() {
  {
    MutexLock lock(&mutex_);
    stopping_ = true;
  }
  ready_.notify_all();
  for (std::thread& thread : threads_) thread.join();
}

void WorkPool::Post(Key key, std::function<void()> task) {
  {
    MutexLock lock(&mutex_);
    std::deque<std::function<void()>>& queue = queues_[key];
    if (queue.empty()) turn_.push_back(key);
    queue.push_back(std::move(task));
    ++queued_;
  }
  ready_.notify_one();
}

size_t WorkPool::queued() const {
  MutexLock lock(&mutex_);
  return queued_;
}

void WorkPool::Work() {
  while (true) {
    std::function<void()> task;
    {
      MutexLock lock(&mutex_);
      mutex_.Await(ready_, [this]() ABSL_NO_THREAD_SAFETY_ANALYSIS { return HasWorkOrStopping(); });
      if (turn_.empty()) return;  // stopping and drained
      const Key key = turn_.front();
      turn_.pop_front();
      auto queue = queues_.find(key);
      task = std::move(queue->second.front());
      queue->second.pop_front();
      --queued_;
      if (queue->second.empty()) {
        queues_.erase(queue);
      } else {
        turn_.push_back(key);  // its next task waits for every other key's turn
      }
    }
    try {
      task();
    } catch (const std::exception& error) {
      spdlog::error("work pool: a task threw and was dropped: {}", error.what());
    } catch (...) {
      spdlog::error("work pool: a task threw a non-standard exception and was dropped");
    }
  }
}

}  // namespace mocap

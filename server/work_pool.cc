#include "server/work_pool.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
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

WorkPool::WorkPool(int threads, Clock clock) : clock_(std::move(clock)) {
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

std::int64_t WorkPool::SteadyNanoseconds() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

void WorkPool::Post(Key key, std::function<void()> task) {
  {
    MutexLock lock(&mutex_);
    keys_[key].queue.push_back({next_sequence_++, std::move(task)});
    ++queued_;
  }
  ready_.notify_one();
}

size_t WorkPool::queued() const {
  MutexLock lock(&mutex_);
  return queued_;
}

std::map<WorkPool::Key, WorkPool::KeyState>::iterator WorkPool::PickLocked(std::int64_t now, std::int64_t* tag) {
  auto best = keys_.end();
  std::int64_t best_tag = 0;
  for (auto it = keys_.begin(); it != keys_.end();) {
    KeyState& state = it->second;
    if (state.queue.empty()) {
      // Idle and owing nothing: forgotten (it would restart at the virtual time anyway).
      if (state.running.empty() && state.finish <= virtual_time_) {
        it = keys_.erase(it);
      } else {
        ++it;
      }
      continue;
    }
    std::int64_t key_tag = std::max(virtual_time_, state.finish);
    for (std::int64_t started : state.running) key_tag += std::max<std::int64_t>(0, now - started - kMinimumCharge);
    if (best == keys_.end() || key_tag < best_tag ||
        (key_tag == best_tag && state.queue.front().sequence < best->second.queue.front().sequence)) {
      best = it;
      best_tag = key_tag;
    }
    ++it;
  }
  *tag = best_tag;
  return best;
}

void WorkPool::FinishedLocked(Key key, std::int64_t started, std::int64_t now) {
  auto it = keys_.find(key);
  KeyState& state = it->second;
  state.running.erase(std::find(state.running.begin(), state.running.end(), started));
  state.finish += std::max<std::int64_t>(0, now - started - kMinimumCharge);
  if (state.queue.empty() && state.running.empty() && state.finish <= virtual_time_) keys_.erase(it);
}

void WorkPool::Work() {
  while (true) {
    std::function<void()> task;
    Key key = kSharedKey;
    std::int64_t started = 0;
    {
      MutexLock lock(&mutex_);
      mutex_.Await(ready_, [this]() ABSL_NO_THREAD_SAFETY_ANALYSIS { return HasWorkOrStopping(); });
      if (queued_ == 0) return;  // stopping and drained
      started = clock_();
      std::int64_t tag = 0;
      auto picked = PickLocked(started, &tag);
      key = picked->first;
      KeyState& state = picked->second;
      state.finish = std::max(state.finish, virtual_time_) + kMinimumCharge;  // the rest when it ends
      virtual_time_ = tag;
      task = std::move(state.queue.front().task);
      state.queue.pop_front();
      state.running.push_back(started);
      --queued_;
    }
    try {
      task();
    } catch (const std::exception& error) {
      spdlog::error("work pool: a task threw and was dropped: {}", error.what());
    } catch (...) {
      spdlog::error("work pool: a task threw a non-standard exception and was dropped");
    }
    task = nullptr;  // its captures go before the charge: their destructors are the task's work
    MutexLock lock(&mutex_);
    FinishedLocked(key, started, clock_());
  }
}

}  // namespace mocap

#include "server/work_pool.h"

#include <exception>

#include <spdlog/spdlog.h>

namespace mocap {

WorkPool::WorkPool(int threads) {
  for (int i = 0; i < threads; ++i) threads_.emplace_back([this] { Work(); });
}

WorkPool::~WorkPool() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  ready_.notify_all();
  for (std::thread& thread : threads_) thread.join();
}

void WorkPool::Post(Key key, std::function<void()> task) {
  {
    std::lock_guard lock(mutex_);
    std::deque<std::function<void()>>& queue = queues_[key];
    if (queue.empty()) turn_.push_back(key);
    queue.push_back(std::move(task));
    ++queued_;
  }
  ready_.notify_one();
}

size_t WorkPool::queued() const {
  std::lock_guard lock(mutex_);
  return queued_;
}

void WorkPool::Work() {
  while (true) {
    std::function<void()> task;
    {
      std::unique_lock lock(mutex_);
      ready_.wait(lock, [&] { return stopping_ || !turn_.empty(); });
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

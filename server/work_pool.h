// WorkPool: a fixed set of threads running queued tasks in order of arrival. gRPC callback
// handlers post their store and parsing work here, so no gRPC thread blocks and no call owns a
// thread while it waits for its client.
#pragma once

#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace mocap {

class WorkPool {
 public:
  explicit WorkPool(int threads);
  // Runs the queued tasks, then joins the threads.
  ~WorkPool();
  WorkPool(const WorkPool&) = delete;
  WorkPool& operator=(const WorkPool&) = delete;

  // Thread-safe. Tasks must not throw.
  void Post(std::function<void()> task);

 private:
  void Work();
  std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<std::function<void()>> tasks_;
  bool stopping_ = false;
  std::vector<std::thread> threads_;
};

}  // namespace mocap

// Runs work(i) for i in [0, n) on `threads` threads (each takes the next index in turn), and
// returns the first error any call returned; the others still run. Used by mocap-eval to prepare
// and reconstruct clips, each call single-threaded.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "absl/status/status.h"

namespace mocap::eval {

inline absl::Status ParallelFor(size_t n, int threads, const std::function<absl::Status(size_t)>& work) {
  std::atomic<size_t> next{0};
  std::mutex mutex;
  absl::Status first_error = absl::OkStatus();
  auto run = [&] {
    for (size_t i = next++; i < n; i = next++) {
      absl::Status status = work(i);
      if (status.ok()) continue;
      std::lock_guard<std::mutex> lock(mutex);
      if (first_error.ok()) first_error = std::move(status);
    }
  };
  std::vector<std::thread> pool;
  for (int t = 0; t < std::max(1, threads); ++t) pool.emplace_back(run);
  for (std::thread& t : pool) t.join();
  return first_error;
}

// All the machine's cores (at least one).
inline int AllCores() { return static_cast<int>(std::max(1u, std::thread::hardware_concurrency())); }

}  // namespace mocap::eval

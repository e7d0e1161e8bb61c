#include "server/bounded_shutdown.h"

#include <atomic>
#include <memory>
#include <thread>

namespace mocap {

bool WaitForShutdown(std::function<void()> shutdown, std::chrono::milliseconds limit, const sigset_t& signals) {
  // Shared with the thread, which may outlive this call.
  auto done = std::make_shared<std::atomic<bool>>(false);
  std::thread([shutdown = std::move(shutdown), done] {
    shutdown();
    done->store(true);
  }).detach();
  const auto deadline = std::chrono::steady_clock::now() + limit;
  const timespec poll{.tv_sec = 0, .tv_nsec = 20'000'000};  // 20 ms
  while (!done->load()) {
    if (std::chrono::steady_clock::now() >= deadline) return false;
    // A signal in the set ends the wait; a timeout (EAGAIN) or an interruption goes on.
    if (sigtimedwait(&signals, nullptr, &poll) > 0) return done->load();
  }
  return true;
}

}  // namespace mocap

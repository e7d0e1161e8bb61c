// WaitForShutdown (server/bounded_shutdown.h): a shutdown that returns is waited for; one that
// would not end, or a second signal, stops the wait at its bound.
#include "server/bounded_shutdown.h"

#include <gtest/gtest.h>
#include <pthread.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <memory>
#include <thread>

namespace mocap {
namespace {

using std::chrono::milliseconds;

sigset_t NoSignals() {
  sigset_t none;
  sigemptyset(&none);
  return none;
}

TEST(BoundedShutdownTest, AShutdownThatEndsIsWaitedFor) {
  bool ran = false;
  EXPECT_TRUE(WaitForShutdown(
      [&ran] {
        std::this_thread::sleep_for(milliseconds(50));
        ran = true;
      },
      milliseconds(5000), NoSignals()));
  EXPECT_TRUE(ran);
}

TEST(BoundedShutdownTest, AShutdownThatHangsIsLeftAtTheBound) {
  auto release = std::make_shared<std::atomic<bool>>(false);
  const auto start = std::chrono::steady_clock::now();
  EXPECT_FALSE(WaitForShutdown(
      [release] {
        while (!release->load()) std::this_thread::sleep_for(milliseconds(5));
      },
      milliseconds(200), NoSignals()));
  const auto waited = std::chrono::steady_clock::now() - start;
  EXPECT_GE(waited, milliseconds(200));
  EXPECT_LT(waited, milliseconds(3000));
  release->store(true);  // let the detached thread end before the test binary does
  std::this_thread::sleep_for(milliseconds(50));
}

TEST(BoundedShutdownTest, ASecondSignalEndsTheWait) {
  sigset_t usr1;
  sigemptyset(&usr1);
  sigaddset(&usr1, SIGUSR1);
  sigset_t previous;
  ASSERT_EQ(pthread_sigmask(SIG_BLOCK, &usr1, &previous), 0);  // taken by sigtimedwait, as mocapd serve does
  auto release = std::make_shared<std::atomic<bool>>(false);
  const pthread_t waiting = pthread_self();  // directed at this thread, which blocks it: never the default action
  std::thread second([waiting] {
    std::this_thread::sleep_for(milliseconds(100));
    pthread_kill(waiting, SIGUSR1);
  });
  const auto start = std::chrono::steady_clock::now();
  EXPECT_FALSE(WaitForShutdown(
      [release] {
        while (!release->load()) std::this_thread::sleep_for(milliseconds(5));
      },
      milliseconds(20000), usr1));
  EXPECT_LT(std::chrono::steady_clock::now() - start, milliseconds(10000));
  second.join();
  release->store(true);
  std::this_thread::sleep_for(milliseconds(50));
  pthread_sigmask(SIG_SETMASK, &previous, nullptr);
}

}  // namespace
}  // namespace mocap

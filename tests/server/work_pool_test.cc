// WorkPool (server/work_pool.h): every task runs once; keys are served by the time their tasks
// cost, so a key with a long queue delays another key's task by at most one task, cheap tasks of
// several keys take turns one each, and a key of expensive tasks gets fewer of them; a throwing
// task is dropped and the pool goes on; the destructor runs what is still queued. Waits are on
// events (futures, latches), never on the clock; the tests of order run on a clock their tasks
// advance.
#include "server/work_pool.h"

#include <sched.h>
#include <sys/resource.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <future>
#include <latch>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace mocap {
// Named, so that helpers do not meet other files' in a unity batch.
namespace work_pool_test {
namespace {

// Holds a pool's threads inside a task until Open(): tasks posted meanwhile queue up, so a test
// decides what is queued before anything of it runs.
class Gate {
 public:
  // Posts one blocking task per pool thread and returns once every thread is inside one.
  // The tasks hold their own references, so the gate may go before the pool.
  void Close(WorkPool& pool, int threads) {
    auto entered = std::make_shared<std::latch>(threads);
    for (int i = 0; i < threads; ++i) {
      pool.Post([open = open_, entered] {
        entered->count_down();
        open.wait();
      });
    }
    entered->wait();
  }
  void Open() { release_.set_value(); }

 private:
  std::promise<void> release_;
  std::shared_future<void> open_ = release_.get_future().share();
};

// The order tasks ran in (by label), filled by the pool's threads.
class Journal {
 public:
  void Add(std::string label) {
    std::lock_guard lock(mutex_);
    labels_.push_back(std::move(label));
  }
  std::vector<std::string> labels() const {
    std::lock_guard lock(mutex_);
    return labels_;
  }

 private:
  mutable std::mutex mutex_;
  std::vector<std::string> labels_;
};

// A clock that moves only when a task says it took time.
class ManualClock {
 public:
  WorkPool::Clock clock() {
    return [this] { return now_.load(); };
  }
  void AdvanceMilliseconds(int milliseconds) { now_.fetch_add(std::int64_t{milliseconds} * 1'000'000); }

 private:
  std::atomic<std::int64_t> now_{1'000'000'000};
};

TEST(WorkPoolTest, RunsEveryTaskOnceFromManyPostingThreads) {
  for (const WorkPool::PromptLane lane : {WorkPool::PromptLane::kNo, WorkPool::PromptLane::kYes}) {
    SCOPED_TRACE(lane == WorkPool::PromptLane::kYes ? "with the prompt lane" : "without the prompt lane");
    constexpr int kPosters = 4, kPerPoster = 500;
    std::vector<std::atomic<int>> runs(kPosters * kPerPoster);
    std::latch done(kPosters * kPerPoster);
    {
      WorkPool pool(3, lane);
      std::vector<std::thread> posters;
      for (int p = 0; p < kPosters; ++p) {
        posters.emplace_back([&, p] {
          for (int i = 0; i < kPerPoster; ++i) {
            const int id = p * kPerPoster + i;
            pool.Post(static_cast<WorkPool::Key>(id % 7), [&runs, &done, id] {
              runs[id].fetch_add(1);
              done.count_down();
            });
          }
        });
      }
      for (std::thread& poster : posters) poster.join();
      done.wait();
      EXPECT_EQ(pool.queued(), 0u);
    }
    for (size_t id = 0; id < runs.size(); ++id) ASSERT_EQ(runs[id].load(), 1) << "task " << id;
  }
}

TEST(WorkPoolTest, OneKeysLongQueueDelaysAnotherKeyByAtMostOneTurn) {
  Journal journal;
  std::latch done(51);  // declared before the pool: it outlives the pool's threads
  ManualClock clock;
  WorkPool pool(1, clock.clock());
  Gate gate;
  gate.Close(pool, 1);
  constexpr WorkPool::Key kFlood = 7, kVictim = 8;
  for (int i = 0; i < 50; ++i) {
    pool.Post(kFlood, [&, i] {
      journal.Add("flood" + std::to_string(i));
      done.count_down();
    });
  }
  pool.Post(kVictim, [&] {
    journal.Add("victim");
    done.count_down();
  });
  EXPECT_EQ(pool.queued(), 51u);
  gate.Open();
  done.wait();
  const std::vector<std::string> order = journal.labels();
  ASSERT_EQ(order.size(), 51u);
  // The flood's first task had its turn before the victim's key was queued; then the victim's.
  EXPECT_EQ(order[0], "flood0");
  EXPECT_EQ(order[1], "victim");
  // Within a key, first in first out.
  for (int i = 1; i < 50; ++i) EXPECT_EQ(order[i + 1], "flood" + std::to_string(i));
}

TEST(WorkPoolTest, CheapTasksOfSeveralKeysTakeTurnsOneEachAndKeepTheirOwnOrder) {
  Journal journal;
  std::latch done(3 + 2 + 1);
  ManualClock clock;
  WorkPool pool(1, clock.clock());
  Gate gate;
  gate.Close(pool, 1);
  auto post = [&](WorkPool::Key key, const std::string& label) {
    pool.Post(key, [&journal, &done, label] {
      journal.Add(label);
      done.count_down();
    });
  };
  post(1, "a0");
  post(1, "a1");
  post(1, "a2");
  post(2, "b0");
  post(2, "b1");
  post(3, "c0");
  gate.Open();
  done.wait();
  EXPECT_EQ(journal.labels(), (std::vector<std::string>{"a0", "b0", "c0", "a1", "b1", "a2"}));
}

TEST(WorkPoolTest, KeysGetTheSameTimeNotTheSameNumberOfTasks) {
  // One thread, two keys with everything queued: 10 ms tasks against 1 ms tasks. While both keys
  // have work, the time each has been given never differs by more than one expensive task.
  constexpr int kExpensive = 10, kCheap = 100;
  Journal journal;
  std::latch done(kExpensive + kCheap);
  ManualClock clock;
  WorkPool pool(1, clock.clock());
  Gate gate;
  gate.Close(pool, 1);
  for (int i = 0; i < kExpensive; ++i) {
    pool.Post(1, [&] {
      clock.AdvanceMilliseconds(10);
      journal.Add("expensive");
      done.count_down();
    });
  }
  for (int i = 0; i < kCheap; ++i) {
    pool.Post(2, [&] {
      clock.AdvanceMilliseconds(1);
      journal.Add("cheap");
      done.count_down();
    });
  }
  gate.Open();
  done.wait();
  const std::vector<std::string> order = journal.labels();
  ASSERT_EQ(order.size(), static_cast<size_t>(kExpensive + kCheap));
  int expensive_ms = 0, cheap_ms = 0, expensive_left = kExpensive, cheap_left = kCheap;
  for (size_t i = 0; i < order.size(); ++i) {
    if (order[i] == "expensive") {
      expensive_ms += 10;
      --expensive_left;
    } else {
      cheap_ms += 1;
      --cheap_left;
    }
    if (expensive_left > 0 && cheap_left > 0) {
      EXPECT_LE(std::abs(expensive_ms - cheap_ms), 10) << "after task " << i;
    }
  }
  // Turns by task would have run all ten expensive tasks among the first twenty.
  const auto first_twenty = std::vector<std::string>(order.begin(), order.begin() + 20);
  EXPECT_LE(std::count(first_twenty.begin(), first_twenty.end(), "expensive"), 2);
}

TEST(WorkPoolTest, AKeyIsChargedForItsRunningTaskBeforeItEnds) {
  // Key 1 ran a 50 ms task; key 2's task has been running for 100 ms on the other thread. A free
  // thread serves key 1 before key 2's next task, though key 2 has finished nothing yet.
  Journal journal;
  std::latch all_done(3);
  ManualClock clock;
  WorkPool pool(2, clock.clock());
  std::latch first_done(1), long_started(1);
  pool.Post(1, [&] {
    clock.AdvanceMilliseconds(50);
    first_done.count_down();
  });
  first_done.wait();
  // Its cost is charged after it returns, from the clock then: key 2 must not advance the clock
  // before that (key 1 would be charged key 2's 100 ms too).
  while (pool.running() > 0) std::this_thread::yield();
  std::promise<void> release_long;
  std::shared_future<void> long_may_end = release_long.get_future().share();
  pool.Post(2, [&, long_may_end] {
    clock.AdvanceMilliseconds(100);
    long_started.count_down();
    long_may_end.wait();
    journal.Add("long");
    all_done.count_down();
  });
  long_started.wait();
  // The other thread is held while both keys queue their next task, key 2's first.
  Gate gate;
  gate.Close(pool, 1);
  pool.Post(2, [&] {
    journal.Add("second of key 2");
    all_done.count_down();
  });
  pool.Post(1, [&] {
    journal.Add("key 1");
    all_done.count_down();
    release_long.set_value();
  });
  gate.Open();
  all_done.wait();
  const std::vector<std::string> order = journal.labels();
  ASSERT_EQ(order.size(), 3u);
  EXPECT_EQ(order[0], "key 1");  // the other two end in either order, on two threads
}

TEST(WorkPoolTest, KeysWithLongTasksLeaveOneThreadForShortWork) {
  // Key 1's tasks are long (one ran 60 ms). While one of them runs, its next waits though a
  // thread is free, and key 2's short task takes that thread.
  Journal journal;
  std::latch done(4);
  ManualClock clock;
  WorkPool pool(2, clock.clock(), clock.clock());
  std::latch first_done(1), long_started(1), short_ran(1);
  pool.Post(1, [&] {
    clock.AdvanceMilliseconds(60);
    first_done.count_down();
    done.count_down();
  });
  first_done.wait();
  // The pool books the 60 ms after the task returns: wait for that, or key 1 still looks short.
  while (pool.running() > 0) std::this_thread::yield();
  std::promise<void> release;
  std::shared_future<void> may_end = release.get_future().share();
  pool.Post(1, [&, may_end] {
    long_started.count_down();
    may_end.wait();
    journal.Add("long");
    done.count_down();
  });
  long_started.wait();
  pool.Post(1, [&] {
    journal.Add("second long");
    done.count_down();
  });
  pool.Post(2, [&] {
    journal.Add("short");
    short_ran.count_down();
    done.count_down();
  });
  short_ran.wait();  // ran on the free thread; the second long task is still queued
  EXPECT_EQ(pool.queued(), 1u);
  EXPECT_EQ(journal.labels(), std::vector<std::string>{"short"});
  release.set_value();
  done.wait();
  EXPECT_EQ(journal.labels(), (std::vector<std::string>{"short", "long", "second long"}));
}

TEST(WorkPoolTest, ATaskThatTookLongButWorkedLittleLeavesItsKeyShort) {
  // A task's work is its thread's CPU time: one that took 30 ms of the pool's clock (preempted on a
  // loaded machine, or waiting) without working does not make its key long, so the key's next
  // tasks still use both threads.
  std::latch done(3);
  ManualClock clock;
  WorkPool pool(2, clock.clock());  // the work clock: each thread's own CPU time
  std::latch first_done(1), waiting(1);
  pool.Post(1, [&] {
    clock.AdvanceMilliseconds(30);
    first_done.count_down();
    done.count_down();
  });
  first_done.wait();
  std::promise<void> release, next_ran;
  std::shared_future<void> may_end = release.get_future().share();
  pool.Post(1, [&, may_end] {
    waiting.count_down();
    may_end.wait();
    done.count_down();
  });
  waiting.wait();
  pool.Post(1, [&] {
    next_ran.set_value();
    done.count_down();
  });
  // On the second thread while the first still waits: the key is not long (a long key's next
  // task would wait for the first to end).
  const bool ran_beside = next_ran.get_future().wait_for(std::chrono::seconds(10)) == std::future_status::ready;
  release.set_value();
  done.wait();
  EXPECT_TRUE(ran_beside);
}

TEST(WorkPoolTest, APoolOfOneThreadHoldsNothingBack) {
  // Long tasks run one after another on the only thread.
  std::latch done(2);
  ManualClock clock;
  WorkPool pool(1, clock.clock(), clock.clock());
  pool.Post(1, [&] {
    clock.AdvanceMilliseconds(30);
    done.count_down();
  });
  pool.Post(1, [&] { done.count_down(); });
  done.wait();
}

// What a task running on the pool reads from AnotherKeyWaits at each of a test's steps: the task
// waits at step i until the test has set the scene, reads, and tells the test it has.
class YieldProbe {
 public:
  explicit YieldProbe(int steps) : steps_(steps), read_(steps) {}
  // The task's body.
  void Run() {
    const int steps = steps_;  // the test may leave once the last step is signalled
    for (int i = 0; i < steps; ++i) {
      go_[i].get_future().wait();
      read_[i] = WorkPool::AnotherKeyWaits();
      done_[i].set_value();
    }
  }
  // The test's side: lets the task read at step i, returns what it read.
  bool Read(int i) {
    go_[i].set_value();
    done_[i].get_future().wait();
    return read_[i];
  }

 private:
  int steps_;
  std::vector<bool> read_;
  std::promise<void> go_[4];
  std::promise<void> done_[4];
};

TEST(WorkPoolTest, ATaskIsToldWhenAnotherKeyWaitsForAThread) {
  // The pool goes first (reset at the end): its threads are joined while what their tasks touch
  // still lives (ASan: a task read the probe's step count after the test had left its scope).
  auto pool = std::make_unique<WorkPool>(2);
  YieldProbe probe(4);
  pool->Post(1, [&] { probe.Run(); });
  EXPECT_FALSE(probe.Read(0)) << "nothing queued";

  // A second key's task takes the idle thread: nobody waits.
  std::promise<void> second_started;
  std::promise<void> release_second;
  pool->Post(2, [&, release = release_second.get_future().share()] {
    second_started.set_value();
    release.wait();
  });
  second_started.get_future().wait();
  EXPECT_FALSE(probe.Read(1)) << "the other key's task got a thread";

  // More of a running key's own work does not wait for another key.
  std::latch own_ran(1);
  pool->Post(1, [&] { own_ran.count_down(); });
  EXPECT_FALSE(probe.Read(2)) << "only key 1's own task queued";

  // A third key with nothing running waits: both threads are busy.
  std::latch third_ran(1);
  pool->Post(3, [&] { third_ran.count_down(); });
  EXPECT_TRUE(probe.Read(3)) << "key 3 waits for a thread";
  EXPECT_FALSE(WorkPool::AnotherKeyWaits()) << "outside the pool's threads it is always false";

  release_second.set_value();
  third_ran.wait();
  own_ran.wait();
  pool.reset();
}

// The calling thread's nice value.
int ThisThreadsNiceness() { return getpriority(PRIO_PROCESS, static_cast<id_t>(gettid())); }

TEST(WorkPoolTest, AQuietKeysTaskRunsOnThePromptLaneWhileEveryThreadIsBusy) {
  WorkPool pool(1, WorkPool::PromptLane::kYes);
  constexpr WorkPool::Key kFlood = 1, kQuiet = 2;
  const int process_niceness = ThisThreadsNiceness();  // the pool's threads start from it
  // A quiet key's task while a thread is free: the free thread takes it, not the lane.
  std::promise<int> first_niceness;
  std::promise<void> release_first;
  pool.Post(kFlood, [&, release = release_first.get_future().share()] {
    first_niceness.set_value(ThisThreadsNiceness());
    release.wait();
  });
  const int pool_niceness = first_niceness.get_future().get();
  if (process_niceness < 5) {
    EXPECT_EQ(pool_niceness, 5) << "the pool's threads run below the process's";
  }

  // Every thread is busy. More of the flood is not quiet (its key has a task running): it waits
  // for the pool's thread, the lane being free.
  std::latch second_ran(1);
  pool.Post(kFlood, [&] { second_ran.count_down(); });
  // A quiet key's task runs at once, on the lane, at the priority of the process's threads.
  std::promise<int> quiet_niceness;
  pool.Post(kQuiet, [&] { quiet_niceness.set_value(ThisThreadsNiceness()); });
  EXPECT_EQ(quiet_niceness.get_future().get(), process_niceness);
  EXPECT_EQ(pool.queued(), 1u) << "the flood's second task still waits for the pool's thread";

  release_first.set_value();
  second_ran.wait();
}

TEST(WorkPoolTest, ABulkPoolRunsBelowTheComputePool) {
  if (ThisThreadsNiceness() >= 5) GTEST_SKIP() << "this process already runs at nice 5 or lower priority";
  auto niceness_of = [](WorkPool& pool) {
    std::promise<int> niceness;
    pool.Post([&] { niceness.set_value(ThisThreadsNiceness()); });
    return niceness.get_future().get();
  };
  WorkPool compute(1, WorkPool::Priority::kCompute);
  WorkPool bulk(1, WorkPool::Priority::kBulk);
  EXPECT_EQ(niceness_of(compute), 5);
  EXPECT_EQ(niceness_of(bulk), 10) << "imports and the store's calls yield to live sessions' compute";
}

// The calling thread's scheduling policy, real-time priority and nice value.
struct ThreadScheduling {
  int policy = -1;
  int priority = -1;
  int niceness = 0;
};
ThreadScheduling ThisThreadsScheduling() {
  sched_param param{};
  sched_getparam(0, &param);
  return {sched_getscheduler(0), param.sched_priority, ThisThreadsNiceness()};
}

// The calling thread under SCHED_RR 3, as `chrt --rr 3` starts a server; `started` gets 0 or the
// errno (no CAP_SYS_NICE: the test skips).
bool EnterRealTimeAt3(std::promise<int>& started) {
  sched_param param{};
  param.sched_priority = 3;
  const int error = sched_setscheduler(0, SCHED_RR, &param) == 0 ? 0 : errno;
  started.set_value(error);
  return error == 0;
}

TEST(WorkPoolTest, UnderARealTimePolicyThePoolsKeepTheirOrder) {
  // A server started by `chrt --rr 3`: its threads inherit SCHED_RR 3 from the thread that starts them.
  std::promise<ThreadScheduling> lane, compute, bulk;
  std::shared_future<ThreadScheduling> lane_got_future = lane.get_future().share();
  std::shared_future<ThreadScheduling> compute_got_future = compute.get_future().share();
  std::promise<int> started;
  std::thread server_main([&] {
    if (!EnterRealTimeAt3(started)) return;
    WorkPool compute_pool(1, WorkPool::PromptLane::kYes);
    WorkPool bulk_pool(1, WorkPool::Priority::kBulk);
    std::promise<void> release;
    compute_pool.Post(1, [&, wait = release.get_future().share()] {
      compute.set_value(ThisThreadsScheduling());
      wait.wait();
    });
    compute_got_future.wait();  // the pool's one thread is busy: a quiet key's task goes to the lane
    compute_pool.Post(2, [&] { lane.set_value(ThisThreadsScheduling()); });
    bulk_pool.Post([&] { bulk.set_value(ThisThreadsScheduling()); });
    lane_got_future.wait();
    release.set_value();
  });
  const int error = started.get_future().get();
  if (error != 0) {
    server_main.join();
    GTEST_SKIP() << "this process may not use SCHED_RR (" << std::strerror(error) << "): needs CAP_SYS_NICE";
  }
  const ThreadScheduling lane_got = lane_got_future.get();
  const ThreadScheduling compute_got = compute_got_future.get();
  const ThreadScheduling bulk_got = bulk.get_future().get();
  server_main.join();
  EXPECT_EQ(lane_got.policy, SCHED_RR);
  EXPECT_EQ(lane_got.priority, 3) << "the prompt lane runs at the server's own (gRPC's) priority";
  EXPECT_EQ(compute_got.policy, SCHED_RR);
  EXPECT_EQ(compute_got.priority, 2) << "compute one below the transport";
  EXPECT_EQ(bulk_got.policy, SCHED_OTHER) << "bulk work leaves the real-time policy";
  EXPECT_EQ(bulk_got.niceness, 10);
}

// Under a real-time policy a backlogged key's tasks leave it (work_pool.h): real-time work that
// fills the cores makes the kernel stop every real-time thread for the starved ones.
TEST(WorkPoolTest, UnderARealTimePolicyABackloggedKeysTasksLeaveIt) {
  std::atomic<std::int64_t> now{0};
  std::promise<int> started;
  std::promise<ThreadScheduling> first, backlogged, after;
  std::thread server_main([&] {
    if (!EnterRealTimeAt3(started)) return;
    WorkPool pool(1, WorkPool::PromptLane::kNo, [&] { return now.load(); });
    std::promise<void> release;
    std::shared_future<void> released = release.get_future().share();
    std::promise<void> first_running;
    pool.Post(1, [&] {
      first.set_value(ThisThreadsScheduling());
      first_running.set_value();
      released.wait();
    });
    pool.Post(1, [&] { backlogged.set_value(ThisThreadsScheduling()); });  // queued behind it
    first_running.get_future().wait();
    now = WorkPool::kBackloggedAfter + 1;  // the key has been busy that long without a break
    release.set_value();
    while (pool.queued() > 0 || pool.running() > 0) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    pool.Post(1, [&] { after.set_value(ThisThreadsScheduling()); });  // idle before: a fresh start
  });
  const int error = started.get_future().get();
  if (error != 0) {
    server_main.join();
    GTEST_SKIP() << "this process may not use SCHED_RR (" << std::strerror(error) << "): needs CAP_SYS_NICE";
  }
  const ThreadScheduling first_got = first.get_future().get();
  const ThreadScheduling backlogged_got = backlogged.get_future().get();
  const ThreadScheduling after_got = after.get_future().get();
  server_main.join();
  EXPECT_EQ(first_got.policy, SCHED_RR);
  EXPECT_EQ(first_got.priority, 2);
  EXPECT_EQ(backlogged_got.policy, SCHED_OTHER) << "a backlogged key's task leaves the real-time policy";
  EXPECT_EQ(backlogged_got.niceness, 5) << "at compute's niceness, above bulk work";
  EXPECT_EQ(after_got.policy, SCHED_RR) << "the next key that is not backlogged has it back";
  EXPECT_EQ(after_got.priority, 2);
}

TEST(WorkPoolTest, ThePromptLanesPoolRunsWhatIsQueuedBeforeTheDestructorReturns) {
  std::atomic<int> ran{0};
  {
    WorkPool pool(2, WorkPool::PromptLane::kYes);
    for (int i = 0; i < 200; ++i) pool.Post(static_cast<WorkPool::Key>(i % 3), [&ran] { ran.fetch_add(1); });
  }  // ~WorkPool: the lane's thread ends as well, though most tasks were never quiet
  EXPECT_EQ(ran.load(), 200);
}

TEST(WorkPoolTest, AThrowingTaskIsDroppedAndThePoolKeepsWorking) {
  std::atomic<int> after{0};
  std::latch done(3);
  WorkPool pool(1);  // one thread: if a throw killed it, nothing after would run
  pool.Post([] { throw std::runtime_error("task failed"); });
  pool.Post([&] {
    after.fetch_add(1);
    done.count_down();
  });
  pool.Post(5, [] { throw 42; });  // not a std::exception
  pool.Post(5, [&] {
    after.fetch_add(1);
    done.count_down();
  });
  pool.Post([&] {
    after.fetch_add(1);
    done.count_down();
  });
  done.wait();
  EXPECT_EQ(after.load(), 3);
  EXPECT_EQ(pool.queued(), 0u);
}

TEST(WorkPoolTest, DestructorRunsTheQueuedTasksThenJoins) {
  std::atomic<int> ran{0};
  auto pool = std::make_unique<WorkPool>(2);
  Gate gate;
  gate.Close(*pool, 2);
  for (int i = 0; i < 40; ++i) pool->Post(static_cast<WorkPool::Key>(i % 3), [&ran] { ran.fetch_add(1); });
  EXPECT_EQ(pool->queued(), 40u);
  // The destructor waits for the gated threads; opening the gate lets them drain the queue.
  std::thread destroyer([&pool] { pool.reset(); });
  gate.Open();
  destroyer.join();
  EXPECT_EQ(ran.load(), 40);
}

TEST(WorkPoolTest, TasksPostedByRunningTasksRunBeforeTheDestructorReturns) {
  std::atomic<int> ran{0};
  {
    std::function<void(int)> chain;
    WorkPool pool(1);
    Gate gate;
    gate.Close(pool, 1);
    // A task that posts its successor, ten deep: all are queued work when the destructor drains.
    chain = [&](int depth) {
      ran.fetch_add(1);
      if (depth < 10) pool.Post([&chain, depth] { chain(depth + 1); });
    };
    pool.Post([&chain] { chain(1); });
    gate.Open();
  }  // ~WorkPool
  EXPECT_EQ(ran.load(), 10);
}

TEST(WorkPoolTest, QueuedCountsTasksNotYetStarted) {
  std::latch done(8);
  WorkPool pool(2);
  EXPECT_EQ(pool.queued(), 0u);
  Gate gate;
  gate.Close(pool, 2);
  EXPECT_EQ(pool.queued(), 0u);  // the gate tasks have started
  for (int i = 0; i < 5; ++i) pool.Post(1, [&done] { done.count_down(); });
  for (int i = 0; i < 3; ++i) pool.Post(2, [&done] { done.count_down(); });
  EXPECT_EQ(pool.queued(), 8u);
  gate.Open();
  done.wait();
  EXPECT_EQ(pool.queued(), 0u);
}

}  // namespace
}  // namespace work_pool_test
}  // namespace mocap

// WorkPool (server/work_pool.h): every task runs once; keys are served round robin, so a key with
// a long queue delays another key's task by at most one turn; a throwing task is dropped and the
// pool goes on; the destructor runs what is still queued. Waits are on events (futures, latches),
// never on the clock.
#include "server/work_pool.h"

#include <gtest/gtest.h>

#include <atomic>
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

TEST(WorkPoolTest, RunsEveryTaskOnceFromManyPostingThreads) {
  constexpr int kPosters = 4, kPerPoster = 500;
  std::vector<std::atomic<int>> runs(kPosters * kPerPoster);
  std::latch done(kPosters * kPerPoster);
  {
    WorkPool pool(3);
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

TEST(WorkPoolTest, OneKeysLongQueueDelaysAnotherKeyByAtMostOneTurn) {
  Journal journal;
  std::latch done(51);  // declared before the pool: it outlives the pool's threads
  WorkPool pool(1);
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

TEST(WorkPoolTest, KeysTakeTurnsOneTaskEachAndKeepTheirOwnOrder) {
  Journal journal;
  std::latch done(3 + 2 + 1);
  WorkPool pool(1);
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

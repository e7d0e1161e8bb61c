// StorePool (server/store_pool.h): one connection per borrower at a time, connections reused once
// returned, writes seen by other leases, read-only pools that refuse writes and a missing file.
#include "server/store_pool.h"

#include <gtest/gtest.h>

#include <barrier>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "tests/support/temp_dir.h"

namespace mocap {
// Named, so that helpers do not meet other files' in a unity batch.
namespace store_pool_test {
namespace {

class StorePoolTest : public ::testing::Test {
 protected:
  testing::ScopedTempDir temp_;
  const std::filesystem::path store_ = temp_.path() / "var" / "mocap.db";
};

TEST_F(StorePoolTest, OpenCreatesTheStoreAndLeasesReuseReturnedConnections) {
  auto pool = StorePool::Open(store_);
  ASSERT_TRUE(pool.ok()) << pool.status();
  EXPECT_TRUE(std::filesystem::exists(store_));
  EXPECT_FALSE((*pool)->read_only());
  MotionStore* first = nullptr;
  {
    auto lease = (*pool)->Acquire();
    ASSERT_TRUE(lease.ok()) << lease.status();
    first = lease->get();
  }
  // The one idle connection comes back, again and again; no new one is opened.
  for (int i = 0; i < 5; ++i) {
    auto lease = (*pool)->Acquire();
    ASSERT_TRUE(lease.ok()) << lease.status();
    EXPECT_EQ(lease->get(), first);
  }
}

TEST_F(StorePoolTest, TwoLeasesAtOnceAreTwoConnections) {
  auto pool = StorePool::Open(store_);
  ASSERT_TRUE(pool.ok()) << pool.status();
  auto a = (*pool)->Acquire();
  auto b = (*pool)->Acquire();
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_NE(a->get(), b->get());
  // A write through one is read through the other (the same file).
  auto created = (*a)->CreateEmptyDatabase("walks", 30.0);
  ASSERT_TRUE(created.ok()) << created.status();
  auto found = (*b)->FindDatabase("walks");
  ASSERT_TRUE(found.ok()) << found.status();
  EXPECT_EQ(found->ref, created->ref);
}

// Borrowers that all hold a lease at the same moment each have their own connection, use it
// concurrently, and give it back: afterwards the pool holds exactly that many idle connections.
TEST_F(StorePoolTest, ConcurrentBorrowersEachGetTheirOwnConnection) {
  constexpr int kBorrowers = 6, kRounds = 5;
  auto opened = StorePool::Open(store_);
  ASSERT_TRUE(opened.ok()) << opened.status();
  StorePool& pool = **opened;
  {
    auto lease = pool.Acquire();
    ASSERT_TRUE(lease.ok());
    ASSERT_TRUE((*lease)->CreateEmptyDatabase("shared", 30.0).ok());
  }
  std::mutex mutex;
  std::set<MotionStore*> seen;
  std::vector<std::set<MotionStore*>> round_leases(kRounds);
  std::vector<std::string> errors;
  std::barrier step(kBorrowers);
  std::vector<std::thread> borrowers;
  for (int t = 0; t < kBorrowers; ++t) {
    borrowers.emplace_back([&, t] {
      for (int round = 0; round < kRounds; ++round) {
        step.arrive_and_wait();  // every lease of the last round has been given back
        auto lease = pool.Acquire();
        if (!lease.ok()) {
          {
            std::lock_guard lock(mutex);
            errors.push_back(std::string(lease.status().message()));
          }
          step.arrive_and_wait();
          continue;
        }
        auto found = (*lease)->FindDatabase("shared");
        auto listed = (*lease)->ListDatabases();
        {
          std::lock_guard lock(mutex);
          if (!found.ok()) errors.push_back(std::string(found.status().message()));
          if (!listed.ok() || listed->size() != 1) errors.push_back("borrower " + std::to_string(t) + ": bad listing");
          seen.insert(lease->get());
          round_leases[round].insert(lease->get());
        }
        step.arrive_and_wait();  // every borrower holds its lease now, and gives it back below
      }
    });
  }
  for (std::thread& borrower : borrowers) borrower.join();
  ASSERT_TRUE(errors.empty()) << errors.front();
  // While all held one, no two shared a connection.
  for (int round = 0; round < kRounds; ++round) EXPECT_EQ(round_leases[round].size(), static_cast<size_t>(kBorrowers));
  // Never more connections than borrowers at once: the returned ones were reused every round.
  EXPECT_EQ(seen.size(), static_cast<size_t>(kBorrowers));
  // All returned: that many can be held again, all of them known ones.
  std::vector<StorePool::Lease> held;
  for (int i = 0; i < kBorrowers; ++i) {
    auto lease = pool.Acquire();
    ASSERT_TRUE(lease.ok());
    EXPECT_TRUE(seen.count(lease->get())) << "lease " << i << " is a new connection";
    held.push_back(*std::move(lease));
  }
}

TEST_F(StorePoolTest, ReadOnlyPoolsNeedTheFileAndRefuseWrites) {
  auto missing = StorePool::Open(store_, /*read_only=*/true);
  EXPECT_FALSE(missing.ok());
  EXPECT_FALSE(std::filesystem::exists(store_)) << "a read-only open created the store";
  {
    auto writable = StorePool::Open(store_);
    ASSERT_TRUE(writable.ok()) << writable.status();
    auto lease = (*writable)->Acquire();
    ASSERT_TRUE((*lease)->CreateEmptyDatabase("walks", 30.0).ok());
  }
  auto pool = StorePool::Open(store_, /*read_only=*/true);
  ASSERT_TRUE(pool.ok()) << pool.status();
  EXPECT_TRUE((*pool)->read_only());
  auto a = (*pool)->Acquire();
  auto b = (*pool)->Acquire();  // a second connection, opened read-only too
  ASSERT_TRUE(a.ok() && b.ok());
  for (auto* lease : {&*a, &*b}) {
    EXPECT_TRUE((*lease)->FindDatabase("walks").ok());
    EXPECT_FALSE((*lease)->CreateEmptyDatabase("more", 30.0).ok());
  }
}

}  // namespace
}  // namespace store_pool_test
}  // namespace mocap

// VersionRegistry (server/version_registry.h): one build per database version and variant,
// shared by every caller; a new version replaces the older one of the same variant only.
#include "server/version_registry.h"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <atomic>
#include <future>
#include <memory>
#include <string>

#include "server/work_pool.h"
#include "tests/support/temp_dir.h"

namespace mocap {
// Named, so that helpers do not meet other files' in a unity batch.
namespace version_registry_test {
namespace {

class VersionRegistryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto pool = StorePool::Open(temp_.path() / "mocap.db");
    ASSERT_TRUE(pool.ok()) << pool.status();
    stores_ = *std::move(pool);
    registry_ = std::make_unique<VersionRegistry>(
        *stores_, /*max_cached=*/8, "test value", [this](MotionStore&, const DatabaseVersion& version) {
          ++builds_;
          builder_niceness_ = getpriority(PRIO_PROCESS, static_cast<id_t>(gettid()));
          return VersionRegistry::Value(
              std::make_shared<const std::string>(version.content_stamp + "/" + version.variant));
        });
  }
  // The value for `version`, waiting for its build.
  std::shared_ptr<const std::string> Get(const DatabaseVersion& version) {
    std::promise<std::shared_ptr<const std::string>> value;
    registry_->Acquire(version, [&](absl::StatusOr<VersionRegistry::Value> built) {
      value.set_value(built.ok() ? std::static_pointer_cast<const std::string>(*built) : nullptr);
    });
    return value.get_future().get();
  }
  testing::ScopedTempDir temp_;
  std::unique_ptr<StorePool> stores_;
  std::atomic<int> builds_{0};
  std::atomic<int> builder_niceness_{0};
  std::unique_ptr<VersionRegistry> registry_;
};

TEST_F(VersionRegistryTest, VariantsOfOneVersionAreBuiltAndKeptApart) {
  const DatabaseVersion a{.content_stamp = "v1", .variant = "bone-directions"};
  DatabaseVersion b = a;
  b.variant = "body-scale";
  EXPECT_EQ(*Get(a), "v1/bone-directions");
  EXPECT_EQ(*Get(a), "v1/bone-directions");
  EXPECT_EQ(builds_, 1);
  EXPECT_EQ(*Get(b), "v1/body-scale");
  EXPECT_EQ(builds_, 2);

  // A new version of variant a replaces a's old entry, not b's.
  DatabaseVersion a2 = a;
  a2.content_stamp = "v2";
  EXPECT_EQ(*Get(a2), "v2/bone-directions");
  EXPECT_EQ(builds_, 3);
  EXPECT_EQ(*Get(b), "v1/body-scale");
  EXPECT_EQ(builds_, 3);
  EXPECT_EQ(*Get(a), "v1/bone-directions");  // the old version had to be built again
  EXPECT_EQ(builds_, 4);
  EXPECT_EQ(registry_->builds(), 4);
}

// The niceness a pool of `priority` runs its tasks at.
int PoolNiceness(WorkPool::Priority priority) {
  WorkPool pool(1, priority);
  std::promise<int> niceness;
  pool.Post([&] { niceness.set_value(getpriority(PRIO_PROCESS, static_cast<id_t>(gettid()))); });
  return niceness.get_future().get();
}

// A build is bulk work: it runs as an import does, below the compute pool's live sessions.
TEST_F(VersionRegistryTest, BuildsRunAtTheBulkPoolsPriority) {
  EXPECT_EQ(*Get({.content_stamp = "v1"}), "v1/");
  EXPECT_EQ(builder_niceness_.load(), PoolNiceness(WorkPool::Priority::kBulk));
  EXPECT_GT(builder_niceness_.load(), PoolNiceness(WorkPool::Priority::kCompute));
}

}  // namespace
}  // namespace version_registry_test
}  // namespace mocap

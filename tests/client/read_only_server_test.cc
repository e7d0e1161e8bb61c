// `mocapd serve --read-only`: a store file rolled out to replicas is served without a single
// write (no -wal/-shm files, the file unchanged), reads and reconstructions work, every write RPC
// answers FAILED_PRECONDITION, and a store with changes still in its WAL is refused at start.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include "client/wrist_input/wrist_source.h"
#include "tests/support/server_fixture.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;

std::string Contents(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

class ReadOnlyServerTest : public testing::ServerFixture {};

TEST_F(ReadOnlyServerTest, ServesReadsAndSessionsAndRefusesEveryWrite) {
  StartServer();
  ImportWalks(*Connect(keys_["acme"]));
  ASSERT_EQ(server_->Stop(), 0);
  const std::string before = Contents(store_);
  ASSERT_FALSE(fs::exists(store_.string() + "-wal"));

  StartServer({"--read-only"});
  auto client = Connect(keys_["acme"]);
  auto databases = client->ListDatabases();
  ASSERT_TRUE(databases.ok()) << databases.status();
  ASSERT_EQ(databases->size(), 1u);
  auto samples = WristsFromBvh(WriteClip("query.bvh", 40), 0.0, 1);
  ASSERT_TRUE(samples.ok()) << samples.status();
  v1::SessionConfig config;
  config.set_database("walks");
  config.mutable_overrides()->set_ankle_candidates(40);
  config.mutable_overrides()->set_pose_neighbours(30);
  auto reconstructed = client->ReconstructTrajectory(config, *samples);
  ASSERT_TRUE(reconstructed.ok()) << reconstructed.status();
  EXPECT_EQ(reconstructed->frames_size(), 40);

  auto import = client->ImportFiles("walks", {WriteClip("more.bvh", 50)});
  EXPECT_EQ(import.status().code(), absl::StatusCode::kFailedPrecondition) << import.status();
  EXPECT_NE(import.status().message().find("read-only"), std::string::npos) << import.status();
  EXPECT_EQ(client->CreateDatabase("new").status().code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_EQ(client->DeleteDatabase("walks").code(), absl::StatusCode::kFailedPrecondition);
  auto clips = client->ListClips("walks");
  ASSERT_TRUE(clips.ok()) << clips.status();
  EXPECT_EQ(client->DeleteClip("walks", clips->front().id()).code(), absl::StatusCode::kFailedPrecondition);
  // Another tenant's key still sees nothing of it, and no key is still refused.
  EXPECT_EQ(Connect(keys_["other"])->ListClips("walks").status().code(), absl::StatusCode::kNotFound);

  ASSERT_EQ(server_->Stop(), 0);
  EXPECT_FALSE(fs::exists(store_.string() + "-wal"));
  EXPECT_FALSE(fs::exists(store_.string() + "-shm"));
  EXPECT_TRUE(Contents(store_) == before) << "the read-only server changed the store file";
}

TEST_F(ReadOnlyServerTest, AStoreWithChangesStillInItsWalIsRefused) {
  // A writer holding the store open keeps its last change in the WAL (not yet checkpointed).
  auto writer = std::move(MotionStore::Open(store_)).value();
  TenantDirectory tenants(*writer);
  ASSERT_TRUE(tenants.CreateTenant("third").ok());
  ASSERT_GT(fs::file_size(store_.string() + "-wal"), 0u);
  auto server = std::make_unique<testing::ServerProcess>(MOCAPD_PATH, store_, dir_ / "ro.log",
                                                         std::vector<std::string>{"--read-only"});
  EXPECT_TRUE(server->address().empty());
  EXPECT_NE(Contents(dir_ / "ro.log").find("not yet checkpointed"), std::string::npos) << Contents(dir_ / "ro.log");
}

}  // namespace
}  // namespace mocap

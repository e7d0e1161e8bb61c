// Issue #14, faults: what a store and a client see when the server is killed during an import,
// when the disk fills during an import, and when a client is killed mid-stream. (SIGTERM with
// live sessions: ReconstructionServiceTest.ShutdownEndsLiveSessionsAfterTheirFrames.)
#include <signal.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <future>
#include <sstream>
#include <string>
#include <thread>

#include "tests/support/server_fixture.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

class FaultTest : public testing::ServerFixture {
 protected:
  // `count` distinct synthetic walks of ~`frames` frames each.
  std::vector<fs::path> Walks(int count, int frames) {
    std::vector<fs::path> files;
    for (int i = 0; i < count; ++i) {
      files.push_back(WriteClip("walk" + std::to_string(i) + ".bvh", frames + 7 * i));
    }
    return files;
  }
  // PRAGMA integrity_check of the store file, opened read-only beside no server.
  std::string IntegrityCheck() const {
    sqlite3* db = nullptr;
    std::string result = "cannot open";
    if (sqlite3_open_v2(store_.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK) {
      sqlite3_stmt* statement = nullptr;
      if (sqlite3_prepare_v2(db, "PRAGMA integrity_check", -1, &statement, nullptr) == SQLITE_OK &&
          sqlite3_step(statement) == SQLITE_ROW) {
        result = reinterpret_cast<const char*>(sqlite3_column_text(statement, 0));
      }
      sqlite3_finalize(statement);
    }
    sqlite3_close(db);
    return result;
  }
  // Clips in the tenant's database, 0 when it does not exist; −1 on error.
  long ClipsIn(client::Client& client, const std::string& database) {
    auto databases = client.ListDatabases();
    if (!databases.ok()) return -1;
    for (const v1::DatabaseSummary& summary : *databases) {
      if (summary.name() == database) return summary.clip_count();
    }
    return 0;
  }
  double SessionsActive(client::Client& client) {
    auto text = client.GetMetrics();
    if (!text.ok()) return -1;
    std::istringstream lines(*text);
    for (std::string line; std::getline(lines, line);) {
      if (line.rfind("mocap_sessions_active ", 0) == 0) return std::stod(line.substr(22));
    }
    return -1;
  }
};

// kill -9 during a gRPC import, at five different points: the store opens, passes
// integrity_check, and holds all of the batch or none of it.
TEST_F(FaultTest, KilledDuringAGrpcImportTheStoreHoldsAllOrNoneOfTheBatch) {
  const std::vector<fs::path> files = Walks(12, 900);
  int none = 0, all = 0;
  for (int round = 0; round < 5; ++round) {
    StartServer();
    auto acme = Connect(keys_["acme"]);
    const std::string database = "walks" + std::to_string(round);
    auto import = std::async(std::launch::async, [&] { return acme->ImportFiles(database, files); });
    std::this_thread::sleep_for(std::chrono::milliseconds(40 + 60 * round));
    server_->Kill();
    auto result = import.get();
    EXPECT_EQ(IntegrityCheck(), "ok") << "round " << round;
    StartServer();
    const long clips = ClipsIn(*Connect(keys_["acme"]), database);
    EXPECT_TRUE(clips == 0 || clips == static_cast<long>(files.size()))
        << "round " << round << ": " << clips << " of " << files.size() << " clips stored";
    (clips == 0 ? none : all) += 1;
    if (result.ok()) {
      EXPECT_EQ(clips, static_cast<long>(files.size())) << "the client was told OK";
    }
  }
  EXPECT_GT(none, 0) << "every import finished before the kill: the test did not kill one mid-batch";
}

// A full disk during an import (the server may not grow any file past 1.5 MB): the import fails
// with a status, the server stays up, nothing of the batch is stored, and once there is room
// again the same import succeeds.
TEST_F(FaultTest, AFullDiskFailsTheImportAndLosesNothing) {
  StartServer();
  auto acme = Connect(keys_["acme"]);
  ImportWalks(*acme, "before");
  const long stored_before = ClipsIn(*acme, "before");
  server_.reset();
  StartServer({}, 1'500'000);
  acme = Connect(keys_["acme"]);
  const std::vector<fs::path> files = Walks(10, 1500);
  auto result = acme->ImportFiles("walks", files);
  ASSERT_FALSE(result.ok()) << "the import fitted in 1.5 MB: make it larger";
  EXPECT_TRUE(result.status().code() == absl::StatusCode::kResourceExhausted ||
              result.status().code() == absl::StatusCode::kInternal)
      << result.status();
  EXPECT_EQ(ClipsIn(*acme, "walks"), 0) << "the server is down or stored part of the batch";
  EXPECT_EQ(ClipsIn(*acme, "before"), stored_before);
  server_.reset();
  EXPECT_EQ(IntegrityCheck(), "ok");
  StartServer();
  acme = Connect(keys_["acme"]);
  auto again = acme->ImportFiles("walks", files);
  ASSERT_TRUE(again.ok()) << again.status();
  EXPECT_EQ(ClipsIn(*acme, "walks"), static_cast<long>(files.size()));
}

// A client killed mid-stream (its process gone, no cancel sent): the session is freed at once by
// the broken connection, and at the latest by the idle limit.
TEST_F(FaultTest, AKilledClientsSessionIsFreed) {
  StartServer({"--idle-seconds", "3"});
  auto acme = Connect(keys_["acme"]);
  ImportWalks(*acme);
  const std::string clip = WriteClip("query.bvh", 90).string();
  const std::string key = keys_["acme"];
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    execl(MOCAP_LOAD_PATH, MOCAP_LOAD_PATH, "--address", server_->address().c_str(), "--key", key.c_str(), "--database",
          "walks", "--bvh", clip.c_str(), "--streams", "1", "--seconds", "120", "--ramp-seconds", "0",
          static_cast<char*>(nullptr));
    _exit(127);
  }
  double active = 0;
  for (int i = 0; i < 200 && active < 1; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    active = SessionsActive(*acme);
  }
  ASSERT_EQ(active, 1) << "the client's session did not start";
  kill(child, SIGKILL);
  waitpid(child, nullptr, 0);
  const auto killed = Clock::now();
  while (SessionsActive(*acme) != 0 && Clock::now() - killed < std::chrono::seconds(10)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - killed).count();
  EXPECT_EQ(SessionsActive(*acme), 0);
  EXPECT_LT(seconds, 4.0) << "the killed client's session outlived the 3 s idle limit";
}

}  // namespace
}  // namespace mocap

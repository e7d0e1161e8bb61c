// A test fixture with a real store file (tenants "acme" and "other", one key each), a real
// `mocapd serve` on loopback started on demand, and SDK clients: the base of the end-to-end tests.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "mocap/client.h"
#include "motion/bvh/bvh_writer.h"
#include "storage/motion_store.h"
#include "storage/tenant_directory.h"
#include "tests/support/server_process.h"
#include "tests/support/synthetic_clip.h"
#include "tests/support/temp_dir.h"

namespace mocap::testing {

class ServerFixture : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = dir_ / "var" / "mocap.db";
    std::filesystem::create_directories(dir_ / "clips");
    auto store = std::move(MotionStore::Open(store_)).value();
    TenantDirectory tenants(*store);
    for (const char* name : {"acme", "other"}) {
      auto tenant = tenants.CreateTenant(name);
      ASSERT_TRUE(tenant.ok()) << tenant.status();
      keys_[name] = tenants.AddKey(tenant->id)->key;
    }
  }

  // A failed test shows the end of the server's log (the temporary folder goes with the test), so
  // a failure seen only in CI can be read there.
  void TearDown() override {
    if (!HasFailure()) return;
    server_.reset();  // stopped: its log is complete
    std::ifstream log(dir_ / "server.log");
    std::vector<std::string> lines;
    for (std::string line; std::getline(log, line);) lines.push_back(line);
    const size_t first = lines.size() > 40 ? lines.size() - 40 : 0;
    std::cerr << "--- last " << lines.size() - first << " lines of the server's log ---\n";
    for (size_t i = first; i < lines.size(); ++i) std::cerr << lines[i] << "\n";
  }

  void StartServer(const std::vector<std::string>& extra = {}, long max_file_bytes = 0) {
    server_.reset();
    server_ = std::make_unique<ServerProcess>(MOCAPD_PATH, store_, dir_ / "server.log", extra, max_file_bytes);
    ASSERT_FALSE(server_->address().empty()) << "mocapd serve did not start; see " << (dir_ / "server.log");
  }
  std::unique_ptr<client::Client> Connect(const std::string& key) {
    auto client = client::Client::Connect(server_->address(), {.api_key = key});
    EXPECT_TRUE(client.ok());
    return std::move(client).value();
  }
  std::filesystem::path WriteClip(const std::string& name, int frames,
                                  const SyntheticRigOptions& rig = {.extra_root = true}) {
    const std::filesystem::path path = dir_ / "clips" / name;
    EXPECT_TRUE(WriteBvhFile(MakeWalkingClip(rig, frames), path).ok());
    return path;
  }
  // A database "walks" of the tenant: three synthetic walks of 90, 120 and 150 frames (different
  // content, so none is skipped as a duplicate).
  void ImportWalks(client::Client& client, const std::string& database = "walks") {
    std::vector<std::filesystem::path> files;
    for (int frames : {90, 120, 150}) files.push_back(WriteClip("walk" + std::to_string(frames) + ".bvh", frames));
    auto imported = client.ImportFiles(database, files);
    ASSERT_TRUE(imported.ok()) << imported.status();
    ASSERT_EQ(imported->imported_count(), 3);
  }
  std::filesystem::path WriteText(const std::string& name, const std::string& text) {
    const std::filesystem::path path = dir_ / "clips" / name;
    std::ofstream(path) << text;
    return path;
  }

  ScopedTempDir temp_;
  const std::filesystem::path& dir_ = temp_.path();
  std::filesystem::path store_;
  std::map<std::string, std::string> keys_;
  std::unique_ptr<ServerProcess> server_;
};

}  // namespace mocap::testing

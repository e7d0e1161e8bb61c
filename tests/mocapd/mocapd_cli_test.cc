// End-to-end runs of the mocapd binary, as a user would: output, JSON and exit codes.
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "motion/bvh/bvh_writer.h"
#include "tests/support/synthetic_clip.h"
#include "tests/support/temp_dir.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;

struct RunResult {
  int exit_code;
  std::string out;  // stdout only
};

RunResult RunMocapd(const std::string& arguments) {
  const std::string command = std::string(MOCAPD_PATH) + " " + arguments + " 2>/dev/null";
  FILE* pipe = popen(command.c_str(), "r");
  RunResult result{-1, ""};
  if (pipe == nullptr) return result;
  std::array<char, 4096> buffer;
  size_t n;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) result.out.append(buffer.data(), n);
  const int status = pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

class MocapdCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::create_directories(dir_ / "clips");
    for (int i = 0; i < 3; ++i) {
      ASSERT_TRUE(WriteBvhFile(testing::MakeWalkingClip({.extra_root = true}, 30 + i),
                               dir_ / "clips" / ("dataset-2_walk_normal_00" + std::to_string(i) + ".bvh"))
                      .ok());
    }
  }
  testing::ScopedTempDir temp_;
  const fs::path& dir_ = temp_.path();
};

TEST_F(MocapdCliTest, InspectPrintsLandmarksAsJson) {
  const RunResult result = RunMocapd("inspect --json " + (dir_ / "clips" / "dataset-2_walk_normal_000.bvh").string());
  ASSERT_EQ(result.exit_code, 0);
  const auto report = nlohmann::json::parse(result.out).at(0);
  EXPECT_EQ(report["landmarks"]["left_wrist"], "LeftHand");
  EXPECT_EQ(report["landmarks"]["pelvis"], "Hips");
  EXPECT_EQ(report["landmarks"]["left_elbow"], "LeftForeArm");
  EXPECT_EQ(report["landmarks"]["left_shoulder"], "LeftArm");  // past the clavicle
  EXPECT_EQ(report["landmarks"]["right_hip"], "RightUpLeg");
  EXPECT_EQ(report["up_axis"], "+Y");
  EXPECT_EQ(report["frames"], 30);
  EXPECT_EQ(report["units"]["unit"], "cm");
}

TEST_F(MocapdCliTest, ImportThenListDatabases) {
  const std::string store = (dir_ / "var" / "mocap.db").string();
  const RunResult imported =
      RunMocapd("import --quiet --json --store " + store + " --database walks " + (dir_ / "clips").string());
  ASSERT_EQ(imported.exit_code, 0) << imported.out;
  const auto summary = nlohmann::json::parse(imported.out);
  EXPECT_EQ(summary["imported"], 3);
  EXPECT_EQ(summary["frames"], 30 + 31 + 32);

  const RunResult listed = RunMocapd("databases --json --store " + store);
  ASSERT_EQ(listed.exit_code, 0);
  const auto databases = nlohmann::json::parse(listed.out);
  ASSERT_EQ(databases.size(), 1u);
  EXPECT_EQ(databases[0]["name"], "walks");
  EXPECT_EQ(databases[0]["clips"], 3);
  EXPECT_EQ(databases[0]["frames"], 93);
  EXPECT_EQ(databases[0]["joints"], 22);
}

TEST_F(MocapdCliTest, TenantsKeysAndPerTenantDatabases) {
  const std::string store = "--store " + (dir_ / "var" / "mocap.db").string();
  ASSERT_EQ(RunMocapd("tenant create acme " + store).exit_code, 0);
  EXPECT_NE(RunMocapd("tenant create acme " + store).exit_code, 0);  // exists
  const RunResult key = RunMocapd("tenant add-key acme --json " + store);
  ASSERT_EQ(key.exit_code, 0);
  const auto made = nlohmann::json::parse(key.out);
  EXPECT_EQ(made["tenant"], "acme");
  const std::string key_id = made["key_id"];
  EXPECT_EQ(made["key"].get<std::string>().rfind(key_id, 0), 0u);

  ASSERT_EQ(
      RunMocapd("import --quiet --tenant acme --database walks " + store + " " + (dir_ / "clips").string()).exit_code,
      0);
  EXPECT_EQ(nlohmann::json::parse(RunMocapd("databases --json --tenant acme " + store).out).size(), 1u);
  EXPECT_EQ(nlohmann::json::parse(RunMocapd("databases --json " + store).out).size(), 0u);
  EXPECT_NE(RunMocapd("databases --tenant nobody " + store).exit_code, 0);

  auto tenants = nlohmann::json::parse(RunMocapd("tenant list --json " + store).out);
  ASSERT_EQ(tenants.size(), 2u);  // acme and default
  EXPECT_EQ(tenants[0]["name"], "acme");
  EXPECT_EQ(tenants[0]["databases"], 1);
  EXPECT_EQ(tenants[0]["active_keys"], 1);
  ASSERT_EQ(RunMocapd("tenant revoke-key acme " + key_id + " " + store).exit_code, 0);
  EXPECT_NE(RunMocapd("tenant revoke-key acme " + key_id + " " + store).exit_code, 0);
  tenants = nlohmann::json::parse(RunMocapd("tenant list --json " + store).out);
  EXPECT_EQ(tenants[0]["active_keys"], 0);
  EXPECT_FALSE(tenants[0]["keys"][0]["revoked_at"].is_null());
}

TEST_F(MocapdCliTest, BadInputsFailWithNonZeroExit) {
  EXPECT_NE(RunMocapd("inspect " + (dir_ / "missing.bvh").string()).exit_code, 0);
  EXPECT_NE(RunMocapd("import --store " + (dir_ / "s.db").string() + " --database x " + (dir_ / "missing").string())
                .exit_code,
            0);
  EXPECT_NE(RunMocapd("databases --store " + (dir_ / "no-store.db").string()).exit_code, 0);
  EXPECT_FALSE(fs::exists(dir_ / "no-store.db"));            // listing never creates a store
  EXPECT_NE(RunMocapd("import --store x.db").exit_code, 0);  // missing required options
  EXPECT_NE(RunMocapd("").exit_code, 0);
}

}  // namespace
}  // namespace mocap

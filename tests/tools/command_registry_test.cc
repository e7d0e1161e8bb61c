#include "tools/command_line/command_registry.h"

#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace mocap {
namespace {

// A tool with `db` (which runs on its own), `db describe` and `tenant create`.
struct Tool {
  CLI::App app{"tool"};
  CommandRegistry registry;
  std::string ran;
  Tool() {
    CLI::App* db = app.add_subcommand("db");
    CLI::App* describe = db->add_subcommand("describe");
    CLI::App* tenant = app.add_subcommand("tenant");
    CLI::App* create = tenant->add_subcommand("create");
    registry.Add(describe, [this] {
      ran = "db describe";
      return 0;
    });  // registered before its parent
    registry.Add(db, [this] {
      ran = "db";
      return 0;
    });
    registry.Add(create, [this] {
      ran = "tenant create";
      return 3;
    });
  }
  int Run(std::vector<std::string> args) {
    std::vector<const char*> argv{"tool"};
    for (const std::string& arg : args) argv.push_back(arg.c_str());
    app.parse(static_cast<int>(argv.size()), argv.data());
    return registry.RunParsed(app);
  }
};

TEST(CommandRegistryTest, RunsTheDeepestParsedCommand) {
  Tool tool;
  EXPECT_EQ(tool.Run({"db", "describe"}), 0);
  EXPECT_EQ(tool.ran, "db describe");
}

TEST(CommandRegistryTest, RunsAParentOnItsOwn) {
  Tool tool;
  EXPECT_EQ(tool.Run({"db"}), 0);
  EXPECT_EQ(tool.ran, "db");
}

TEST(CommandRegistryTest, ReturnsTheCommandsExitCode) {
  Tool tool;
  EXPECT_EQ(tool.Run({"tenant", "create"}), 3);
  EXPECT_EQ(tool.ran, "tenant create");
}

TEST(CommandRegistryTest, AParsedCommandWithoutARunFunctionIsBadUsage) {
  Tool tool;
  ::testing::internal::CaptureStderr();
  EXPECT_EQ(tool.Run({"tenant"}), 2);
  EXPECT_NE(::testing::internal::GetCapturedStderr().find("tool"), std::string::npos);  // the help text
  EXPECT_TRUE(tool.ran.empty());
}

TEST(CommandRegistryTest, ReportErrorIsExitCodeOne) { EXPECT_EQ(ReportError(absl::NotFoundError("no such store")), 1); }

}  // namespace
}  // namespace mocap

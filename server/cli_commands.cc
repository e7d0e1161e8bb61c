#include "server/cli_commands.h"

#include <functional>
#include <iostream>
#include <memory>
#include <vector>

#include <spdlog/spdlog.h>

#include "server/inspect_command.h"

namespace mocap {
namespace {

struct Command {
  CLI::App* app;
  std::function<int()> run;
};
std::vector<Command>& Commands() {
  static std::vector<Command> commands;
  return commands;
}

// Exit codes: 0 success, 1 a file or store error, 2 bad usage (CLI11).
int ReportError(const absl::Status& status) {
  spdlog::error("{}", std::string(status.message()));
  return 1;
}

std::optional<LengthUnit> ParseUnitOption(const std::string& text) {
  if (text.empty()) return std::nullopt;
  return ParseUnit(text);
}

void RegisterInspect(CLI::App& app) {
  struct Options {
    std::vector<std::string> files;
    bool json = false;
    std::string unit;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = app.add_subcommand("inspect", "Show what the importer finds in BVH files: body groups, "
                                                    "landmarks, up axis, units, frame rate, frame count");
  command->add_option("files", options->files, "BVH files")->required()->check(CLI::ExistingFile);
  command->add_flag("--json", options->json, "Print JSON (one array of reports)");
  command->add_option("--units", options->unit, "Override unit detection")->check(CLI::IsMember({"m", "cm", "mm", "in"}));
  Commands().push_back({command, [options] {
    nlohmann::json all = nlohmann::json::array();
    int failures = 0;
    for (const std::string& file : options->files) {
      auto report = InspectBvhFile(file, InspectOptions{.unit = ParseUnitOption(options->unit)});
      if (!report.ok()) {
        ReportError(report.status());
        ++failures;
        continue;
      }
      if (options->json) {
        all.push_back(*report);
      } else {
        std::cout << FormatInspection(*report);
      }
    }
    if (options->json) std::cout << all.dump(2) << "\n";
    return failures == 0 ? 0 : 1;
  }});
}

}  // namespace

void RegisterCommands(CLI::App& app) {
  RegisterInspect(app);
}

int RunSelectedCommand(CLI::App& app) {
  for (const Command& command : Commands()) {
    if (command.app->parsed()) return command.run();
  }
  std::cerr << app.help();
  return 2;
}

}  // namespace mocap

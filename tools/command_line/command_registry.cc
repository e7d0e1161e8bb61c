#include "tools/command_line/command_registry.h"

#include <iostream>
#include <string>

#include <spdlog/spdlog.h>

namespace mocap {
namespace {

int Depth(const CLI::App* app) {
  int depth = 0;
  for (const CLI::App* parent = app->get_parent(); parent != nullptr; parent = parent->get_parent()) ++depth;
  return depth;
}

}  // namespace

void CommandRegistry::Add(CLI::App* command, Run run) { commands_.push_back({command, std::move(run)}); }

int CommandRegistry::RunParsed(const CLI::App& app) const {
  const Command* chosen = nullptr;
  int chosen_depth = -1;
  for (const Command& command : commands_) {
    if (!command.app->parsed()) continue;
    const int depth = Depth(command.app);
    if (depth >= chosen_depth) {
      chosen = &command;
      chosen_depth = depth;
    }
  }
  if (chosen != nullptr) return chosen->run();
  std::cerr << app.help();
  return 2;
}

int ReportError(const absl::Status& status) {
  spdlog::error("{}", std::string(status.message()));
  return 1;
}

}  // namespace mocap

// Subcommands of mocapd (inspect, import, databases) registered on a CLI11 app.
#pragma once

#include <CLI/CLI.hpp>

namespace mocap {

void RegisterCommands(CLI::App& app);
// Runs the subcommand the user chose; returns the process exit code.
int RunSelectedCommand(CLI::App& app);

}  // namespace mocap

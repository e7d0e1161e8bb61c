// Subcommands of mocapd (inspect, import, databases, similar, tenant, serve) registered on a CLI11
// app, and the small registry they share.
#pragma once

#include <functional>

#include <CLI/CLI.hpp>

#include "absl/status/status.h"

namespace mocap {

void RegisterCommands(CLI::App& app);
// Runs the subcommand the user chose; returns the process exit code.
int RunSelectedCommand(CLI::App& app);

// Registers `run` to be called when `command` (or, for a subcommand of it, `command` itself) is
// the one parsed. For the files that define commands.
void AddCommand(CLI::App* command, std::function<int()> run);
// Logs the error; returns exit code 1 (a file or store error; 2 is bad usage, from CLI11).
int ReportError(const absl::Status& status);

// In their own files.
void RegisterTenantCommands(CLI::App& app);
void RegisterServeCommand(CLI::App& app);


}  // namespace mocap

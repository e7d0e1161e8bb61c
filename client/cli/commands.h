// The `mocap` subcommands: databases, clips, import, export, reconstruct, similar (server calls) and view (local).
#pragma once

#include <functional>

#include <CLI/CLI.hpp>

namespace mocap::cli {

// Registers every subcommand with the global options (--address, --key, --json, ...); the
// returned function runs the one parsed and gives the exit code (0 ok, 1 error, 2 usage).
std::function<int()> RegisterCommands(CLI::App& app);

}  // namespace mocap::cli

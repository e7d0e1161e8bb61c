// mocapd's subcommands, one file each (inspect, import, databases, similar, tenant, serve), all
// registered on one CommandRegistry (tools/command_line/command_registry.h). Commands parse
// options, call a library (storage/, motion/, server/) that returns structs, and format the result
// as text or JSON; they hold no other logic.
#pragma once

#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "motion/core/units.h"
#include "tools/command_line/command_registry.h"

namespace mocap {

void RegisterCommands(CLI::App& app, CommandRegistry& registry);

void RegisterInspectCommand(CLI::App& app, CommandRegistry& registry);
void RegisterImportCommand(CLI::App& app, CommandRegistry& registry);
void RegisterDatabasesCommand(CLI::App& app, CommandRegistry& registry);
void RegisterSimilarCommand(CLI::App& app, CommandRegistry& registry);
void RegisterTenantCommands(CLI::App& app, CommandRegistry& registry);
void RegisterServeCommand(CLI::App& app, CommandRegistry& registry);

// `--units` as given (empty: detect).
std::optional<LengthUnit> ParseUnitOption(const std::string& text);

}  // namespace mocap

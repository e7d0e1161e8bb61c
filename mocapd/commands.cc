#include "mocapd/commands.h"

namespace mocap {

void RegisterCommands(CLI::App& app, CommandRegistry& registry) {
  RegisterInspectCommand(app, registry);
  RegisterImportCommand(app, registry);
  RegisterDatabasesCommand(app, registry);
  RegisterSimilarCommand(app, registry);
  RegisterTenantCommands(app, registry);
  RegisterServeCommand(app, registry);
}

std::optional<LengthUnit> ParseUnitOption(const std::string& text) {
  if (text.empty()) return std::nullopt;
  return ParseUnit(text);
}

}  // namespace mocap

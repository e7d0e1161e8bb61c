// mocapd: the mocap server and its local admin commands.
#include <iostream>

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "mocapd/commands.h"

int main(int argc, char** argv) {
  // Logs go to stderr so that stdout carries only results (JSON for scripts).
  spdlog::set_default_logger(spdlog::stderr_color_mt("mocapd"));
  spdlog::set_pattern("%^%l%$: %v");
  CLI::App app{"mocapd — whole-body motion from wrist trajectories: server and local admin commands"};
  app.require_subcommand(1);
  mocap::CommandRegistry registry;
  mocap::RegisterCommands(app, registry);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    return app.exit(error);
  }
  return registry.RunParsed(app);
}

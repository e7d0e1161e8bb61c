// mocap: the command-line client of a mocapd server (over the SDK, client/include/mocap/client.h).
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "client/cli/commands.h"

int main(int argc, char** argv) {
  // Logs and progress go to stderr; stdout carries only results (JSON with --json).
  spdlog::set_default_logger(spdlog::stderr_color_mt("mocap"));
  spdlog::set_pattern("%^%l%$: %v");
  CLI::App app{"mocap — client of the mocap server: motion databases, BVH import and export"};
  app.require_subcommand(1);
  app.fallthrough();  // global options (--json, --key, ...) may follow the subcommand
  auto run = mocap::cli::RegisterCommands(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    return app.exit(error);
  }
  return run();
}

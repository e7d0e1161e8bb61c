// One subcommand registry for the command-line tools (mocapd, mocap): each command file registers
// its CLI11 subcommand with the function that runs it; after parsing, the tool runs the deepest
// parsed one (`mocap databases describe` before `mocap databases`).
//
// Exit codes, the same in every tool: 0 success, 1 an error (logged), 2 no command given (the
// help on stderr), and CLI11's own codes for bad usage (105 a value failing its check, 106 a
// missing required option, 109 an unknown argument).
#pragma once

#include <functional>
#include <vector>

#include <CLI/CLI.hpp>

#include "absl/status/status.h"

namespace mocap {

class CommandRegistry {
 public:
  using Run = std::function<int()>;
  void Add(CLI::App* command, Run run);
  // Runs the deepest parsed command (the last registered among equals); 2 with the help text on
  // stderr when none of the registered commands was parsed.
  int RunParsed(const CLI::App& app) const;

 private:
  struct Command {
    CLI::App* app;
    Run run;
  };
  std::vector<Command> commands_;
};

// Logs the error's message; returns exit code 1.
int ReportError(const absl::Status& status);

}  // namespace mocap

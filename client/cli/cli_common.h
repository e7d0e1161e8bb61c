// What the `mocap` subcommands share: global options, their registry, JSON output.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <google/protobuf/util/json_util.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "absl/status/status.h"
#include "mocap/client.h"
#include "tools/command_line/command_registry.h"

namespace mocap::cli {

struct GlobalOptions {
  std::string address = "127.0.0.1:50051";
  std::string key;
  std::string tls_root_certs;
  bool tls = false;
  bool json = false;
  double timeout_seconds = 30;
};

inline std::string Json(const google::protobuf::Message& message) {
  std::string out;
  google::protobuf::util::JsonPrintOptions options;
  options.add_whitespace = true;
  options.preserve_proto_field_names = true;
  options.always_print_primitive_fields = true;
  (void)google::protobuf::util::MessageToJsonString(message, &out, options);
  return out;
}

template <typename Message>
std::string JsonList(const std::vector<Message>& messages) {
  nlohmann::json out = nlohmann::json::array();
  for (const Message& message : messages) out.push_back(nlohmann::json::parse(Json(message)));
  return out.dump(2);
}

using Action = std::function<int(client::Client&)>;
using LocalAction = std::function<int()>;  // a command that needs no server

// mocap's commands on the registry every tool uses; most connect to the server before they run.
struct Registry {
  std::shared_ptr<GlobalOptions> global = std::make_shared<GlobalOptions>();
  CommandRegistry commands;
  // A command that talks to the server: connects with the global options, then runs.
  void Add(CLI::App* command, Action action);
  void AddLocal(CLI::App* command, LocalAction action) { commands.Add(command, std::move(action)); }
};

}  // namespace mocap::cli

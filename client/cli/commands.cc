#include "client/cli/commands.h"

#include <cstdlib>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

#include <google/protobuf/util/json_util.h>
#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include "client/cli/cli_common.h"
#include "client/cli/reconstruct_command.h"
#include "client/cli/similar_command.h"
#include "client/cli/view_command.h"
#include "mocap/client.h"
#include "motion/bvh/bvh_files.h"
#include "tools/command_line/progress_bar.h"

namespace mocap::cli {
namespace {

absl::StatusOr<std::unique_ptr<client::Client>> Connect(const GlobalOptions& global) {
  client::ConnectOptions options;
  options.api_key = global.key;
  if (options.api_key.empty()) {
    if (const char* key = std::getenv("MOCAP_API_KEY")) options.api_key = key;
  }
  if (options.api_key.empty()) return absl::UnauthenticatedError("no API key: give --key or set MOCAP_API_KEY");
  options.tls = global.tls || !global.tls_root_certs.empty();
  if (!global.tls_root_certs.empty()) {
    std::ifstream in(global.tls_root_certs);
    if (!in) return absl::NotFoundError("cannot read " + global.tls_root_certs);
    std::stringstream pem;
    pem << in.rdbuf();
    options.tls_root_certs_pem = pem.str();
  }
  options.deadline = std::chrono::milliseconds(static_cast<long>(global.timeout_seconds * 1000));
  return client::Client::Connect(global.address, options);
}

void RegisterDatabases(CLI::App& app, Registry& registry) {
  auto global = registry.global;
  CLI::App* databases = app.add_subcommand("databases", "List, describe, create or delete motion databases");
  CLI::App* list = databases->add_subcommand("list", "List the databases (the default)");
  registry.Add(databases, [global, list](client::Client& client) {
    (void)list;
    auto listed = client.ListDatabases();
    if (!listed.ok()) return ReportError(listed.status());
    if (global->json) {
      std::cout << JsonList(*listed) << "\n";
      return 0;
    }
    if (listed->empty()) std::cout << "no motion databases\n";
    for (const v1::DatabaseSummary& d : *listed) {
      std::cout << d.name() << ": " << d.clip_count() << " clips, " << d.frame_count() << " frames ("
                << d.duration_seconds() / 60.0 << " min) at " << d.frame_rate() << " fps, " << d.joint_count()
                << " joints\n";
    }
    return 0;
  });
  auto name = std::make_shared<std::string>();
  auto frame_rate = std::make_shared<double>(0.0);
  CLI::App* describe = databases->add_subcommand("describe", "Show a database: skeleton, frame rate, counts");
  describe->add_option("name", *name, "Database name")->required();
  registry.Add(describe, [global, name](client::Client& client) {
    auto info = client.DescribeDatabase(*name);
    if (!info.ok()) return ReportError(info.status());
    if (global->json) {
      std::cout << Json(*info) << "\n";
      return 0;
    }
    std::cout << info->name() << ": " << info->clip_count() << " clips, " << info->frame_count() << " frames at "
              << info->frame_rate() << " fps, imported from "
              << (info->source_unit().empty() ? "-" : info->source_unit()) << "; skeleton of "
              << info->skeleton().joints_size() << " joints\n";
    for (const v1::Joint& joint : info->skeleton().joints()) {
      std::cout << "  " << joint.name() << " (parent " << joint.parent() << ", " << v1::BodyGroup_Name(joint.group())
                << ")\n";
    }
    return 0;
  });
  CLI::App* create =
      databases->add_subcommand("create", "Create an empty database (its rig comes with the first import)");
  create->add_option("name", *name, "Database name")->required();
  create->add_option("--frame-rate", *frame_rate, "Frames per second clips are stored at (default 30)")
      ->check(CLI::Range(0.0, 1000.0));
  registry.Add(create, [global, name, frame_rate](client::Client& client) {
    auto created = client.CreateDatabase(*name, *frame_rate);
    if (!created.ok()) return ReportError(created.status());
    if (global->json)
      std::cout << Json(*created) << "\n";
    else
      std::cout << "database '" << created->name() << "' created at " << created->frame_rate() << " fps\n";
    return 0;
  });
  CLI::App* remove = databases->add_subcommand("delete", "Delete a database and all its clips");
  remove->add_option("name", *name, "Database name")->required();
  registry.Add(remove, [global, name](client::Client& client) {
    if (absl::Status status = client.DeleteDatabase(*name); !status.ok()) return ReportError(status);
    if (!global->json) std::cout << "database '" << *name << "' deleted\n";
    return 0;
  });
}

void RegisterClips(CLI::App& app, Registry& registry) {
  auto global = registry.global;
  auto database = std::make_shared<std::string>();
  CLI::App* clips = app.add_subcommand("clips", "List the clips of a database");
  clips->add_option("database", *database, "Database name")->required();
  registry.Add(clips, [global, database](client::Client& client) {
    auto listed = client.ListClips(*database);
    if (!listed.ok()) return ReportError(listed.status());
    if (global->json) {
      std::cout << JsonList(*listed) << "\n";
      return 0;
    }
    for (const v1::Clip& clip : *listed) {
      std::cout << clip.id() << "  " << clip.source_name() << "  " << clip.frame_count() << " frames\n";
    }
    return 0;
  });
}

void RegisterImport(CLI::App& app, Registry& registry) {
  auto global = registry.global;
  struct Options {
    std::string database;
    std::vector<std::string> inputs;
    client::ImportOptions import;
    bool quiet = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = app.add_subcommand("import",
                                         "Send BVH files to a database (created from the first file's rig "
                                         "when missing); atomic per batch");
  command->add_option("--database", options->database, "Database name")->required();
  command->add_option("inputs", options->inputs, "BVH files or folders (searched recursively)")->required();
  command->add_option("--frame-rate", options->import.frame_rate, "Frame rate of a database this import creates");
  command->add_option("--units", options->import.source_unit, "Length unit of the files, overriding detection")
      ->check(CLI::IsMember({"m", "cm", "mm", "in", "cmu"}));
  command->add_option("--batch-size", options->import.batch_size, "Files per atomic batch (0: all in one)")
      ->check(CLI::NonNegativeNumber);
  command->add_flag("--keep-going", options->import.keep_going, "Skip bad files (listed) instead of rolling back");
  command->add_flag("--retarget", options->import.retarget_other_rigs,
                    "Retarget files of another rig onto the database's rig instead of refusing them");
  command->add_flag("--quiet", options->quiet, "No progress bar");
  registry.Add(command, [global, options](client::Client& client) {
    auto files = CollectBvhFiles(options->inputs);
    if (!files.ok()) return ReportError(files.status());
    ProgressBar bar("importing", 1, !options->quiet && !global->json);
    auto result = client.ImportFiles(options->database, *files, options->import, [&](const client::ImportProgress& p) {
      bar.SetTotal(p.bytes_total);
      bar.Update(p.bytes_sent, std::to_string(p.files_sent) + "/" + std::to_string(p.files_total) + " files sent");
    });
    bar.Finish();
    if (!result.ok()) return ReportError(result.status());
    if (global->json) {
      std::cout << Json(*result) << "\n";
      return 0;
    }
    for (const v1::FileResult& file : result->files()) {
      if (file.outcome() != v1::FileResult::OUTCOME_IMPORTED)
        std::cerr << "  " << file.file_name() << ": " << file.error() << "\n";
    }
    std::cout << "database '" << result->database() << "'" << (result->created_database() ? " (created)" : "") << ": "
              << result->imported_count() << " clips imported, " << result->duplicate_count() << " duplicates skipped"
              << (result->failed_count() ? ", " + std::to_string(result->failed_count()) + " files skipped" : "")
              << "; " << result->frame_count() << " frames stored\n";
    return 0;
  });
}

void RegisterExport(CLI::App& app, Registry& registry) {
  struct Options {
    std::string database;
    std::int64_t clip_id = 0;
    std::string output;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = app.add_subcommand(
      "export", "Write a stored clip as BVH (the rig's own unit and axes, as imported; the database's rate)");
  command->add_option("--database", options->database, "Database name")->required();
  command->add_option("--clip", options->clip_id, "Clip id (see `mocap clips`)")->required();
  command->add_option("-o,--output", options->output, "Output file (default: stdout)");
  registry.Add(command, [options](client::Client& client) {
    auto bvh = client.ExportClip(options->database, options->clip_id);
    if (!bvh.ok()) return ReportError(bvh.status());
    if (options->output.empty()) {
      std::cout << *bvh;
      return 0;
    }
    std::ofstream out(options->output, std::ios::binary);
    out << *bvh;
    if (!out) return ReportError(absl::DataLossError("cannot write " + options->output));
    return 0;
  });
}

}  // namespace

std::function<int()> RegisterCommands(CLI::App& app) {
  auto registry = std::make_shared<Registry>();
  GlobalOptions& global = *registry->global;
  app.add_option("--address", global.address, "Server address host:port")
      ->envname("MOCAP_ADDRESS")
      ->capture_default_str();
  app.add_option("--key", global.key, "API key (default: $MOCAP_API_KEY)");
  app.add_flag("--tls", global.tls, "Use TLS with the system's root certificates");
  app.add_option("--tls-root-certs", global.tls_root_certs, "Use TLS trusting these PEM root certificates");
  app.add_flag("--json", global.json, "Print results as JSON");
  app.add_option("--timeout", global.timeout_seconds, "Seconds per call attempt (imports and exports excepted)")
      ->capture_default_str();
  RegisterDatabases(app, *registry);
  RegisterClips(app, *registry);
  RegisterImport(app, *registry);
  RegisterExport(app, *registry);
  RegisterReconstruct(app, *registry);
  RegisterSimilar(app, *registry);
  RegisterView(app, *registry);
  return [registry, &app] { return registry->commands.RunParsed(app); };
}

void Registry::Add(CLI::App* command, Action action) {
  commands.Add(command, [global = global, action = std::move(action)] {
    auto client = Connect(*global);
    if (!client.ok()) return ReportError(client.status());
    return action(**client);
  });
}

}  // namespace mocap::cli

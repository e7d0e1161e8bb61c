#include "server/cli_commands.h"

#include <chrono>
#include <fstream>
#include <functional>
#include <iostream>
#include <memory>
#include <vector>

#include <spdlog/spdlog.h>

#include "motion/core/str_cat.h"
#include "server/import_command.h"
#include "server/inspect_command.h"
#include "cli_util/progress_bar.h"
#include "cli_util/similar_json.h"
#include "server/similar_command.h"
#include "storage/motion_store.h"
#include "storage/tenant_directory.h"

namespace mocap {
namespace {

struct Command {
  CLI::App* app;
  std::function<int()> run;
};
std::vector<Command>& Commands() {
  static std::vector<Command> commands;
  return commands;
}

std::optional<LengthUnit> ParseUnitOption(const std::string& text) {
  if (text.empty()) return std::nullopt;
  return ParseUnit(text);
}

void RegisterInspect(CLI::App& app) {
  struct Options {
    std::vector<std::string> files;
    bool json = false;
    std::string unit;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = app.add_subcommand("inspect", "Show what the importer finds in BVH files: body groups, "
                                                    "landmarks, up axis, units, frame rate, frame count");
  command->add_option("files", options->files, "BVH files")->required()->check(CLI::ExistingFile);
  command->add_flag("--json", options->json, "Print JSON (one array of reports)");
  command->add_option("--units", options->unit, "Override unit detection")->check(CLI::IsMember({"m", "cm", "mm", "in"}));
  AddCommand(command, [options] {
    nlohmann::json all = nlohmann::json::array();
    int failures = 0;
    for (const std::string& file : options->files) {
      auto report = InspectBvhFile(file, InspectOptions{.unit = ParseUnitOption(options->unit)});
      if (!report.ok()) {
        ReportError(report.status());
        ++failures;
        continue;
      }
      if (options->json) {
        all.push_back(*report);
      } else {
        std::cout << FormatInspection(*report);
      }
    }
    if (options->json) std::cout << all.dump(2) << "\n";
    return failures == 0 ? 0 : 1;
  });
}

std::string Thousands(double value) {
  std::string digits = std::to_string(static_cast<long long>(value + 0.5));
  for (int i = static_cast<int>(digits.size()) - 3; i > 0; i -= 3) digits.insert(i, ",");
  return digits;
}

void RegisterImport(CLI::App& app) {
  struct Options {
    ImportOptions import;
    std::string store;
    std::string unit;
    bool json = false;
    bool quiet = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = app.add_subcommand("import", "Import BVH files into a motion database (created from the first "
                                                   "file's rig when missing); atomic per batch");
  command->add_option("--store", options->store, "Motion store file (created when missing)")->required();
  command->add_option("--database", options->import.database, "Motion database name")->required();
  command->add_option("--tenant", options->import.tenant, "Tenant owning the database (default: 'default')");
  command->add_option("inputs", options->import.inputs, "BVH files or folders (searched recursively)")->required();
  command->add_option("--frame-rate", options->import.frame_rate, "Database frame rate when creating it (fps)")
      ->check(CLI::Range(1.0, 1000.0));
  command->add_option("--units", options->unit, "Length unit of the files, overriding detection")
      ->check(CLI::IsMember({"m", "cm", "mm", "in"}));
  command->add_option("--batch-size", options->import.batch_size, "Files per atomic batch (0: all in one)")
      ->check(CLI::NonNegativeNumber);
  command->add_flag("--keep-going", options->import.keep_going, "Skip bad files (listed) instead of rolling back");
  command->add_option("--threads", options->import.threads, "Worker threads (0: one per core)")->check(CLI::NonNegativeNumber);
  command->add_flag("--json", options->json, "Print the summary as JSON");
  command->add_flag("--quiet", options->quiet, "No progress bar");
  AddCommand(command, [options] {
    options->import.store = options->store;
    options->import.unit = ParseUnitOption(options->unit);
    std::optional<ProgressBar> bar;
    const auto start = std::chrono::steady_clock::now();
    auto summary = RunImport(options->import, [&](int done, int total, const ImportSummary& so_far) {
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      if (!bar) bar.emplace("importing", total, !options->quiet && !options->json);
      bar->Update(done, StrCat("files, ", Thousands(so_far.source_frames / std::max(seconds, 1e-3)), " frames/s"));
    });
    if (bar) bar->Finish();
    if (!summary.ok()) return ReportError(summary.status());
    if (options->json) {
      nlohmann::json out = {{"database", summary->database}, {"created_database", summary->created_database},
                            {"files", summary->files}, {"imported", summary->imported},
                            {"duplicates", summary->duplicates}, {"failed", summary->failed},
                            {"frames", summary->frames}, {"source_frames", summary->source_frames},
                            {"motion_seconds", summary->motion_seconds}, {"wall_seconds", summary->wall_seconds},
                            {"source_frames_per_second", summary->frames_per_second()},
                            {"problems", summary->problems}};
      std::cout << out.dump(2) << "\n";
    } else {
      for (const std::string& problem : summary->problems) std::cerr << "  " << problem << "\n";
      std::cout << "database '" << summary->database << "'" << (summary->created_database ? " (created)" : "") << ": "
                << summary->imported << " clips imported, " << summary->duplicates << " duplicates skipped"
                << (summary->failed ? StrCat(", ", summary->failed, " files skipped") : std::string()) << "\n"
                << "  " << Thousands(summary->frames) << " frames at the database rate ("
                << Thousands(summary->source_frames) << " in the files), " << summary->motion_seconds / 60.0
                << " min of motion\n"
                << "  " << summary->wall_seconds << " s wall, " << Thousands(summary->frames_per_second())
                << " frames/s (file frames)\n";
    }
    return 0;
  });
}

void RegisterDatabases(CLI::App& app) {
  struct Options {
    std::string store;
    std::string tenant;
    bool json = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = app.add_subcommand("databases", "List the motion databases of a store");
  command->add_option("--store", options->store, "Motion store file")->required();
  command->add_option("--tenant", options->tenant, "Tenant whose databases to list (default: 'default')");
  command->add_flag("--json", options->json, "Print JSON");
  AddCommand(command, [options] {
    auto store = MotionStore::Open(options->store, StoreOpenOptions{.create_if_missing = false});
    if (!store.ok()) return ReportError(store.status());
    auto tenant = ResolveTenant(**store, options->tenant);
    if (!tenant.ok()) return ReportError(tenant.status());
    auto databases = (*store)->ListDatabases(*tenant);
    if (!databases.ok()) return ReportError(databases.status());
    if (options->json) {
      nlohmann::json out = nlohmann::json::array();
      for (const DatabaseSummary& d : *databases) {
        out.push_back({{"name", d.name}, {"clips", d.num_clips}, {"frames", d.num_frames}, {"seconds", d.seconds()},
                       {"frame_rate", d.frame_rate}, {"unit", std::string(UnitName(d.unit))},
                       {"joints", d.num_joints}, {"root_joint", d.root_joint}});
      }
      std::cout << out.dump(2) << "\n";
      return 0;
    }
    if (databases->empty()) std::cout << "no motion databases in " << options->store << "\n";
    for (const DatabaseSummary& d : *databases) {
      if (!d.has_rig) {
        std::cout << d.name << ": empty (its rig comes with the first import) at " << d.frame_rate << " fps\n";
        continue;
      }
      std::cout << d.name << ": " << d.num_clips << " clips, " << Thousands(d.num_frames) << " frames ("
                << d.seconds() / 60.0 << " min) at " << d.frame_rate << " fps; rig of " << d.num_joints
                << " joints rooted at " << d.root_joint << ", imported from " << UnitName(d.unit) << "\n";
    }
    return 0;
  });
}

void RegisterSimilar(CLI::App& app) {
  struct Options {
    SimilarOptions similar;
    std::string store, query, pose_file, frames, weights = "uniform", sampling = "resample", scaling = "per-chain";
    bool json = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = app.add_subcommand("similar", "Find the poses most similar to a BVH frame's, across skeletons "
                                                    "(any rig: no joint mapping needed)");
  command->add_option("--store", options->store, "Motion store file")->required();
  command->add_option("--database", options->similar.databases, "Database(s) to search (repeat for several)")->required();
  command->add_option("--tenant", options->similar.tenant, "Tenant owning the databases (default: 'default')");
  auto* query = command->add_option("--query", options->query, "BVH file with the query pose(s)")->check(CLI::ExistingFile);
  auto* pose = command->add_option("--query-pose", options->pose_file,
                                   "JSON file with one pose as named joint positions and landmarks (see README)")
                   ->check(CLI::ExistingFile);
  query->excludes(pose);
  command->add_option("--frames", options->frames, "Query frames A:B (inclusive, the file's numbering); default all");
  command->add_option("--step", options->similar.frame_step, "Use every Nth query frame")->check(CLI::PositiveNumber);
  command->add_option("--top", options->similar.search.top_k, "Matches per query frame")->check(CLI::Range(1, 1000));
  command->add_option("--window", options->similar.search.window, "Frames compared around each frame (odd)")
      ->check(CLI::Range(1, 61));
  command->add_option("--weights", options->weights, "Group weights preset")
      ->check(CLI::IsMember({"uniform", "locomotion", "upper-body"}));
  command->add_option("--sampling", options->sampling, "Body points: resample chains or drop joints (the seed's rule)")
      ->check(CLI::IsMember({"resample", "drop"}));
  command->add_option("--scaling", options->scaling,
                      "Body points: each chain by its own length (posture only) or all by the leg length (the seed's)")
      ->check(CLI::IsMember({"per-chain", "body-scale"}));
  command->add_option("--suppress", options->similar.search.suppress_within_frames,
                      "Drop matches within N frames of a better match in the same clip");
  command->add_flag("--exact", options->similar.search.exact, "Compare with every frame (no prefilter)");
  command->add_flag("--json", options->json, "Print JSON");
  AddCommand(command, [options] {
    SimilarOptions& similar = options->similar;
    similar.store = options->store;
    similar.query = options->query;
    if (options->query.empty() && options->pose_file.empty()) {
      return ReportError(absl::InvalidArgumentError("give --query FILE.bvh or --query-pose FILE.json"));
    }
    if (!options->pose_file.empty()) {
      std::ifstream in(options->pose_file);
      try {
        similar.pose = nlohmann::json::parse(in);
      } catch (const nlohmann::json::exception& error) {
        return ReportError(absl::InvalidArgumentError(StrCat(options->pose_file, ": not JSON: ", error.what())));
      }
    }
    if (!options->frames.empty()) {
      auto range = ParseFrameRange(options->frames);
      if (!range.ok()) return ReportError(range.status());
      similar.first_frame = range->first;
      similar.last_frame = range->second;
    }
    similar.search.weights = options->weights == "locomotion"   ? GroupWeights::Locomotion()
                             : options->weights == "upper-body" ? GroupWeights::UpperBody()
                                                                : GroupWeights::Uniform();
    similar.points.sampling =
        options->sampling == "drop" ? PointSampling::kDropNearestEndEffector : PointSampling::kResampleChains;
    similar.points.scaling = options->scaling == "body-scale" ? ChainScaling::kBodyScale : ChainScaling::kPerChain;
    auto result = RunSimilar(similar);
    if (!result.ok()) return ReportError(result.status());
    if (options->json) {
      std::cout << result->dump(2) << "\n";
      return 0;
    }
    PrintSimilarText(*result, std::cout);
    return 0;
  });
}

}  // namespace

void AddCommand(CLI::App* command, std::function<int()> run) { Commands().push_back({command, std::move(run)}); }

// Exit codes: 0 success, 1 a file or store error, 2 bad usage (CLI11).
int ReportError(const absl::Status& status) {
  spdlog::error("{}", std::string(status.message()));
  return 1;
}

void RegisterCommands(CLI::App& app) {
  RegisterInspect(app);
  RegisterImport(app);
  RegisterDatabases(app);
  RegisterSimilar(app);
  RegisterTenantCommands(app);
  RegisterServeCommand(app);

}

int RunSelectedCommand(CLI::App& app) {
  for (const Command& command : Commands()) {
    if (command.app->parsed()) return command.run();
  }
  std::cerr << app.help();
  return 2;
}

}  // namespace mocap

// `mocapd import`: BVH files into a motion database of a store, in atomic batches (storage/import_pipeline.h).
#include <algorithm>
#include <chrono>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "mocapd/commands.h"
#include "motion/core/str_cat.h"
#include "storage/import_pipeline.h"
#include "tools/command_line/number_format.h"
#include "tools/command_line/progress_bar.h"

namespace mocap {
void RegisterImportCommand(CLI::App& app, CommandRegistry& registry) {
  struct Options {
    ImportOptions import;
    std::string store;
    std::string unit;
    bool json = false;
    bool quiet = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = app.add_subcommand("import",
                                         "Import BVH files into a motion database (created from the first "
                                         "file's rig when missing); atomic per batch");
  command->add_option("--store", options->store, "Motion store file (created when missing)")->required();
  command->add_option("--database", options->import.database, "Motion database name")->required();
  command->add_option("--tenant", options->import.tenant, "Tenant owning the database (default: 'default')");
  command->add_option("inputs", options->import.inputs, "BVH files or folders (searched recursively)")->required();
  command->add_option("--frame-rate", options->import.frame_rate, "Database frame rate when creating it (fps)")
      ->check(CLI::Range(1.0, 1000.0));
  command->add_option("--units", options->unit, "Length unit of the files, overriding detection")
      ->check(CLI::IsMember({"m", "cm", "mm", "in", "cmu"}));
  command->add_option("--batch-size", options->import.batch_size, "Files per atomic batch (0: all in one)")
      ->check(CLI::NonNegativeNumber);
  command->add_flag("--keep-going", options->import.keep_going, "Skip bad files (listed) instead of rolling back");
  command->add_flag("--retarget", options->import.retarget_other_rigs,
                    "Retarget files of another rig onto the database's rig instead of refusing them");
  command->add_option("--threads", options->import.threads, "Worker threads (0: one per core)")
      ->check(CLI::NonNegativeNumber);
  command->add_flag("--json", options->json, "Print the summary as JSON");
  command->add_flag("--quiet", options->quiet, "No progress bar");
  registry.Add(command, [options] {
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
      nlohmann::json out = {{"database", summary->database},
                            {"created_database", summary->created_database},
                            {"files", summary->files},
                            {"imported", summary->imported},
                            {"duplicates", summary->duplicates},
                            {"failed", summary->failed},
                            {"frames", summary->frames},
                            {"source_frames", summary->source_frames},
                            {"motion_seconds", summary->motion_seconds},
                            {"wall_seconds", summary->wall_seconds},
                            {"source_frames_per_second", summary->frames_per_second()},
                            {"problems", summary->problems},
                            {"rig_source", summary->rig_source}};
      std::cout << out.dump(2) << "\n";
    } else {
      for (const std::string& problem : summary->problems) std::cerr << "  " << problem << "\n";
      if (!summary->rig_source.empty()) std::cout << "rig (and unit) from " << summary->rig_source << "\n";
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

}  // namespace mocap

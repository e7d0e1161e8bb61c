// `mocapd import`: BVH files into a motion database of a store, in atomic batches.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "motion/core/units.h"

namespace mocap {

struct ImportOptions {
  std::filesystem::path store;
  std::string tenant;  // tenant name; empty: the default tenant
  std::string database;
  std::vector<std::string> inputs;   // files and folders (searched recursively for *.bvh)
  double frame_rate = 30.0;          // used when the database is created
  std::optional<LengthUnit> unit;    // override unit detection when the database is created
  int batch_size = 0;                // files per atomic batch; 0 = all files in one batch
  bool keep_going = false;           // skip bad files (reported) instead of aborting the batch
  bool retarget_other_rigs = false;  // retarget files of another rig onto the database's
  int threads = 0;                   // parse/preprocess workers; 0 = one per core
};

struct ImportSummary {
  std::string database;
  bool created_database = false;
  int files = 0;
  int imported = 0;
  int duplicates = 0;
  int failed = 0;                  // only with keep_going
  std::int64_t frames = 0;         // at the database rate
  std::int64_t source_frames = 0;  // as in the files
  double motion_seconds = 0.0;
  double wall_seconds = 0.0;
  std::vector<std::string> problems;  // "FILE: message" per skipped or duplicate file
  std::string rig_source;             // the file that set a new database's rig (empty: it had one)
  double frames_per_second() const { return wall_seconds > 0 ? source_frames / wall_seconds : 0.0; }
};

// Called after each file with (files done, total files, summary so far).
using ImportProgress = std::function<void(int, int, const ImportSummary&)>;

// Imports; on a bad file without keep_going, the current batch is rolled back (the store is as
// it was before that batch) and the error names the file.
absl::StatusOr<ImportSummary> RunImport(const ImportOptions& options, const ImportProgress& progress = nullptr);

}  // namespace mocap

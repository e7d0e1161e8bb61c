// The store side of an import, shared by `mocapd import` and the ImportBvh RPC: BVH bytes to a
// prepared clip, then clips into a database in atomic batches, with duplicate detection, the
// database created (or its rig fixed) with its first stored clip, and per-file outcomes.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "motion/preprocess/clip_labels.h"
#include "motion/preprocess/clip_preprocessor.h"
#include "storage/motion_store.h"

namespace mocap {

// XXH3-128 of the bytes, hex (the clips.content_hash column).
std::string ContentHash(const std::string& bytes);

// One file read and prepared (or why not; the message starts with the source name and, for
// malformed BVH, its line).
struct PreparedFile {
  absl::Status status = absl::OkStatus();
  std::string hash;
  PreparedClip clip;
};
// Parses `bytes`; with `rig` also prepares the clip for it. `parsed` (optional) gets the clip as
// read, for a caller that still has to fix the database's rig from it.
PreparedFile PrepareBvhBytes(const std::string& bytes, const std::string& source_name, const RigModel* rig,
                             const PreprocessOptions& options, BvhClip* parsed = nullptr);

struct ImportTarget {
  TenantId tenant = kDefaultTenantId;
  std::string database;
  double frame_rate = 30.0;          // used when the database is created
  std::optional<LengthUnit> unit;    // override unit detection when the rig is fixed
  int batch_size = 0;                // files per atomic batch; 0: one batch until Finish
  bool keep_going = false;           // record bad files instead of failing the batch
  bool retarget_other_rigs = false;  // clips of another rig are retargeted onto the database's
  // Hold the batch's clips in memory and write them in one short transaction when it commits,
  // instead of keeping the store's write lock while files arrive (the RPC, whose files come at
  // the client's pace). Refuses batches over max_pending_frames then.
  bool buffer_batch = false;
  std::int64_t max_pending_frames = 2'000'000;
};

struct ImportFileResult {
  enum class Outcome { kImported, kDuplicate, kFailed };
  std::string file_name;
  Outcome outcome = Outcome::kFailed;
  std::int64_t clip_id = 0;  // stored clip, or the stored clip with the same content
  int frames = 0;            // at the database rate
  int source_frames = 0;
  std::string message;  // failure or duplicate explanation
};

struct ImportTotals {
  bool created_database = false;
  int imported = 0;
  int duplicates = 0;
  int failed = 0;
  std::int64_t frames = 0;
  std::int64_t source_frames = 0;
  double motion_seconds = 0.0;
  std::vector<ImportFileResult> files;  // committed files, in order
};

class ImportWriter {
 public:
  // Looks the database up in the tenant (not created before its first clip).
  static absl::StatusOr<std::unique_ptr<ImportWriter>> Start(MotionStore& store, const ImportTarget& target);
  ~ImportWriter();

  // The database's rig, once known (stored, or fixed by SetRig).
  const RigModel* rig() const { return rig_ ? &*rig_ : nullptr; }
  const PreprocessOptions& preprocess() const { return preprocess_; }
  bool database_exists() const { return database_.has_value(); }
  // Fixes the rig of a new (or still empty) database; stored with the first clip.
  void SetRig(RigModel rig) { rig_ = std::move(rig); }
  // Builds the rig from a parsed clip (error names `source_name`).
  absl::Status SetRigFrom(const BvhClip& clip, const std::string& source_name);

  // Adds one file. A failed file: recorded with keep_going; otherwise the batch is rolled back
  // and the returned error (the file's code, "FILE: ... — nothing from this batch was stored")
  // ends the import. Commits when the batch is full.
  absl::Status Add(const std::string& file_name, PreparedFile prepared, ClipLabels labels);
  // Commits the pending batch.
  absl::Status Finish();

  // Every file added so far; the counts cover stored and recorded files (with buffer_batch,
  // the pending batch's clips count once committed).
  const ImportTotals& totals() const { return totals_; }

 private:
  struct Pending {
    std::string file_name;
    PreparedClip clip;
    std::string hash;
    ClipLabels labels;
    size_t result_index;
  };
  ImportWriter(MotionStore& store, ImportTarget target);
  absl::Status EnsureBatch();
  absl::Status Store(Pending pending);
  absl::Status Commit();
  absl::Status Fail(const absl::Status& status);

  MotionStore& store_;
  const ImportTarget target_;
  PreprocessOptions preprocess_;
  std::optional<DatabaseSummary> database_;
  std::optional<RigModel> rig_;
  std::unique_ptr<MotionStore::WriteBatch> batch_;
  std::vector<Pending> pending_;
  std::int64_t pending_frames_ = 0;
  std::set<std::string> hashes_in_batch_;
  int files_in_batch_ = 0;
  int committed_batches_ = 0;
  ImportTotals totals_;
  int committed_imported_ = 0;
};

}  // namespace mocap

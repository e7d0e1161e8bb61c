#include "storage/import_writer.h"

#include <cstdio>

#include <xxhash.h>

#include "motion/bvh/bvh_reader.h"
#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"
#include "motion/retarget/retarget_clip.h"

namespace mocap {

std::string ContentHash(const std::string& bytes) {
  const XXH128_hash_t hash = XXH3_128bits(bytes.data(), bytes.size());
  char text[33];
  std::snprintf(text, sizeof(text), "%016llx%016llx", static_cast<unsigned long long>(hash.high64),
                static_cast<unsigned long long>(hash.low64));
  return text;
}

PreparedFile PrepareBvhBytes(const std::string& bytes, const std::string& source_name, const RigModel* rig,
                             const PreprocessOptions& options, BvhClip* parsed) {
  PreparedFile prepared;
  prepared.hash = ContentHash(bytes);
  absl::StatusOr<BvhClip> clip = ParseBvh(bytes, source_name);
  if (!clip.ok()) {
    prepared.status = clip.status();
    return prepared;
  }
  if (parsed != nullptr) *parsed = *clip;
  if (rig == nullptr) return prepared;
  if (options.retarget_other_rigs && !clip->skeleton.SameRigAs(rig->skeleton)) {
    absl::StatusOr<BvhClip> retargeted = RetargetClipOntoRig(*clip, *rig);
    if (!retargeted.ok()) {
      prepared.status =
          absl::Status(retargeted.status().code(),
                       StrCat(source_name, ": retargeting onto the database's rig: ", retargeted.status().message()));
      return prepared;
    }
    *clip = std::move(*retargeted);
  }
  absl::StatusOr<PreparedClip> ready = PrepareClip(*clip, *rig, options);
  if (ready.ok()) {
    prepared.clip = std::move(*ready);
  } else {
    prepared.status = absl::Status(ready.status().code(), StrCat(source_name, ": ", ready.status().message()));
  }
  return prepared;
}

absl::StatusOr<std::unique_ptr<ImportWriter>> ImportWriter::Start(MotionStore& store, const ImportTarget& target) {
  std::unique_ptr<ImportWriter> writer(new ImportWriter(store, target));
  absl::StatusOr<DatabaseSummary> found = store.FindDatabase(target.database, target.tenant);
  if (found.ok()) {
    writer->database_ = *found;
    writer->preprocess_.frame_rate = found->frame_rate;
    if (found->has_rig) {
      MOCAP_ASSIGN_OR_RETURN(RigModel rig, store.LoadRig(found->ref));
      writer->rig_ = std::move(rig);
    }
  } else if (found.status().code() != absl::StatusCode::kNotFound) {
    return found.status();
  }
  return writer;
}

ImportWriter::ImportWriter(MotionStore& store, ImportTarget target)
    : store_(store),
      target_(std::move(target)),
      preprocess_{
          .frame_rate = target_.frame_rate, .unit = target_.unit, .retarget_other_rigs = target_.retarget_other_rigs} {}

ImportWriter::~ImportWriter() = default;  // an uncommitted batch rolls back

absl::Status ImportWriter::SetRigFrom(const BvhClip& clip, const std::string& source_name) {
  absl::StatusOr<RigModel> rig = BuildRigModel(clip, preprocess_);
  if (!rig.ok()) return absl::Status(rig.status().code(), StrCat(source_name, ": ", rig.status().message()));
  rig_ = std::move(*rig);
  return absl::OkStatus();
}

absl::Status ImportWriter::EnsureBatch() {
  if (!batch_) {
    MOCAP_ASSIGN_OR_RETURN(batch_, store_.BeginWrite());
  }
  return absl::OkStatus();
}

absl::Status ImportWriter::Fail(const absl::Status& status) {
  batch_.reset();  // roll back
  pending_.clear();
  std::string message = StrCat(status.message(), " — nothing from this batch was stored");
  if (committed_batches_ > 0) {
    message += StrCat(" (", committed_batches_, " earlier batch(es) with ", committed_imported_, " clips were kept)");
  }
  return absl::Status(status.code(), message);
}

absl::Status ImportWriter::Add(const std::string& file_name, PreparedFile prepared, ClipLabels labels) {
  ++files_in_batch_;
  ImportFileResult result{.file_name = file_name};
  if (!prepared.status.ok()) {
    if (!target_.keep_going) return Fail(prepared.status);
    result.message = std::string(prepared.status.message());
    ++totals_.failed;
    totals_.files.push_back(std::move(result));
  } else if (hashes_in_batch_.contains(prepared.hash)) {
    result.outcome = ImportFileResult::Outcome::kDuplicate;
    result.message = "already imported (same content earlier in this import)";
    ++totals_.duplicates;
    totals_.files.push_back(std::move(result));
  } else if (rig_ == std::nullopt) {
    return Fail(absl::InternalError(StrCat(file_name, ": the database's rig is not known yet")));
  } else {
    hashes_in_batch_.insert(prepared.hash);
    totals_.files.push_back(std::move(result));
    Pending pending{file_name, std::move(prepared.clip), std::move(prepared.hash), std::move(labels),
                    totals_.files.size() - 1};
    if (target_.buffer_batch) {
      pending_frames_ += pending.clip.num_frames();
      if (pending_frames_ > target_.max_pending_frames) {
        return Fail(
            absl::ResourceExhaustedError(StrCat(file_name, ": this batch would hold over ", target_.max_pending_frames,
                                                " frames; import with a smaller batch size")));
      }
      pending_.push_back(std::move(pending));
    } else {
      MOCAP_RETURN_IF_ERROR(EnsureBatch());
      if (absl::Status stored = Store(std::move(pending)); !stored.ok()) return Fail(stored);
    }
  }
  if (target_.batch_size > 0 && files_in_batch_ >= target_.batch_size) return Commit();
  return absl::OkStatus();
}

absl::Status ImportWriter::Store(Pending pending) {
  ImportFileResult& result = totals_.files[pending.result_index];
  if (!database_) {
    // Created with its first clip, inside that clip's batch: a failed or empty import leaves no
    // empty database behind.
    MOCAP_ASSIGN_OR_RETURN(database_,
                           store_.CreateDatabase(target_.database, *rig_, preprocess_.frame_rate, target_.tenant));
    totals_.created_database = true;
  } else if (!database_->has_rig) {
    // The database was looked up when the import started and may have been deleted since (by
    // this tenant, on another call): SetRig and InsertClip check it inside this batch's write,
    // so the clips land in it or the import ends NotFound; never in another database.
    MOCAP_RETURN_IF_ERROR(store_.SetRig(database_->ref, *rig_));
    database_->has_rig = true;
  }
  MOCAP_ASSIGN_OR_RETURN(std::optional<std::int64_t> existing, store_.FindClipByHash(database_->ref, pending.hash));
  if (existing) {
    result.outcome = ImportFileResult::Outcome::kDuplicate;
    result.clip_id = *existing;
    result.message = StrCat("already imported as clip ", *existing);
    ++totals_.duplicates;
    return absl::OkStatus();
  }
  MOCAP_ASSIGN_OR_RETURN(result.clip_id, store_.InsertClip(database_->ref, pending.file_name, pending.hash,
                                                           pending.labels, pending.clip, *rig_));
  result.outcome = ImportFileResult::Outcome::kImported;
  result.frames = pending.clip.num_frames();
  result.source_frames = pending.clip.source_frames;
  ++totals_.imported;
  totals_.frames += result.frames;
  totals_.source_frames += result.source_frames;
  totals_.motion_seconds += result.frames / preprocess_.frame_rate;
  return absl::OkStatus();
}

absl::Status ImportWriter::Commit() {
  if (!pending_.empty()) {
    MOCAP_RETURN_IF_ERROR(EnsureBatch());
    for (Pending& pending : pending_) {
      if (absl::Status stored = Store(std::move(pending)); !stored.ok()) return Fail(stored);
    }
    pending_.clear();
  }
  if (batch_) {
    if (absl::Status status = batch_->Commit(); !status.ok()) return Fail(status);
    batch_.reset();
  }
  ++committed_batches_;
  committed_imported_ = totals_.imported;
  hashes_in_batch_.clear();
  files_in_batch_ = 0;
  pending_frames_ = 0;
  return absl::OkStatus();
}

absl::Status ImportWriter::Finish() { return files_in_batch_ > 0 ? Commit() : absl::OkStatus(); }

}  // namespace mocap

#include "storage/import_pipeline.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <fstream>
#include <map>
#include <set>
#include <thread>

#include <spdlog/spdlog.h>

#include "motion/bvh/bvh_files.h"
#include "motion/bvh/bvh_reader.h"
#include "motion/core/mutex.h"
#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"
#include "motion/preprocess/clip_labels.h"
#include "motion/preprocess/clip_preprocessor.h"
#include "storage/import_writer.h"
#include "storage/motion_store.h"
#include "storage/tenant_directory.h"

namespace mocap {
namespace {

absl::StatusOr<std::string> ReadFileBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return absl::NotFoundError(StrCat(path.string(), ": cannot open file"));
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) return absl::DataLossError(StrCat(path.string(), ": read failed"));
  return bytes;
}

// Parses and preprocesses files on worker threads, handing results back in file order, with at
// most `window` results waiting (bounded memory).
class PreparePipeline {
 public:
  PreparePipeline(const std::vector<std::filesystem::path>& files, const RigModel& rig,
                  const PreprocessOptions& options, int threads)
      : files_(files), rig_(rig), options_(options), results_(files.size()) {
    window_ = static_cast<size_t>(4 * threads);
    for (int i = 0; i < threads; ++i) workers_.emplace_back([this] { Work(); });
  }
  ~PreparePipeline() {
    {
      MutexLock lock(&mutex_);
      stopping_ = true;
    }
    changed_.notify_all();
    for (std::thread& worker : workers_) worker.join();
  }
  PreparedFile Take(size_t index) {
    MutexLock lock(&mutex_);
    mutex_.Await(changed_, [&]() ABSL_NO_THREAD_SAFETY_ANALYSIS { return Prepared(index); });
    PreparedFile out = std::move(*results_[index]);
    results_[index].reset();
    consumed_ = index + 1;
    changed_.notify_all();
    return out;
  }

 private:
  bool Prepared(size_t index) const ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_) { return results_[index].has_value(); }
  // Stopping, out of files, or a file within the window ahead of the consumer.
  bool CanTakeAFile() const ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_) {
    return stopping_ || next_ >= files_.size() || next_ < consumed_ + window_;
  }
  void Work() {
    while (true) {
      size_t index;
      {
        MutexLock lock(&mutex_);
        mutex_.Await(changed_, [&]() ABSL_NO_THREAD_SAFETY_ANALYSIS { return CanTakeAFile(); });
        if (stopping_ || next_ >= files_.size()) return;
        index = next_++;
      }
      PreparedFile prepared;
      absl::StatusOr<std::string> bytes = ReadFileBytes(files_[index]);
      if (bytes.ok()) {
        prepared = PrepareBvhBytes(*bytes, files_[index].string(), &rig_, options_);
      } else {
        prepared.status = bytes.status();
      }
      {
        MutexLock lock(&mutex_);
        results_[index] = std::move(prepared);
      }
      changed_.notify_all();
    }
  }

  const std::vector<std::filesystem::path>& files_;
  const RigModel& rig_;
  const PreprocessOptions options_;
  mutable Mutex mutex_;
  std::condition_variable changed_;
  std::vector<std::optional<PreparedFile>> results_ ABSL_GUARDED_BY(mutex_);
  size_t next_ ABSL_GUARDED_BY(mutex_) = 0;
  size_t consumed_ ABSL_GUARDED_BY(mutex_) = 0;
  size_t window_ = 8;  // set before the workers start
  bool stopping_ ABSL_GUARDED_BY(mutex_) = false;
  std::vector<std::thread> workers_;
};

}  // namespace

absl::StatusOr<ImportSummary> RunImport(const ImportOptions& options, const ImportProgress& progress) {
  const auto start = std::chrono::steady_clock::now();
  MOCAP_ASSIGN_OR_RETURN(std::vector<std::filesystem::path> files, CollectBvhFiles(options.inputs));
  MOCAP_ASSIGN_OR_RETURN(std::unique_ptr<MotionStore> store, MotionStore::Open(options.store));
  MOCAP_ASSIGN_OR_RETURN(const TenantId tenant, ResolveTenant(*store, options.tenant));
  MOCAP_ASSIGN_OR_RETURN(std::unique_ptr<ImportWriter> writer,
                         ImportWriter::Start(*store, ImportTarget{.tenant = tenant,
                                                                  .database = options.database,
                                                                  .frame_rate = options.frame_rate,
                                                                  .unit = options.unit,
                                                                  .batch_size = options.batch_size,
                                                                  .keep_going = options.keep_going,
                                                                  .retarget_other_rigs = options.retarget_other_rigs}));
  if (writer->database_exists() && std::abs(options.frame_rate - writer->preprocess().frame_rate) > 1e-9) {
    spdlog::warn("database '{}' keeps its {} fps; --frame-rate {} applies only when a database is created",
                 options.database, writer->preprocess().frame_rate, options.frame_rate);
  }
  std::string rig_source;
  if (writer->rig() == nullptr) {
    // The rig comes from the first file named that reads; the database is created (or its rig stored)
    // with the first stored clip, so a failed first batch leaves no database behind.
    absl::Status first_error = absl::OkStatus();
    for (const auto& file : files) {
      BvhClip clip;
      absl::StatusOr<std::string> bytes = ReadFileBytes(file);
      absl::Status status = bytes.status();
      if (status.ok()) status = PrepareBvhBytes(*bytes, file.string(), nullptr, writer->preprocess(), &clip).status;
      if (status.ok()) status = writer->SetRigFrom(clip, file.string());
      if (status.ok()) {
        rig_source = file.string();
        break;
      }
      if (!options.keep_going) return status;
      if (first_error.ok()) first_error = status;
    }
    if (writer->rig() == nullptr) return first_error;
  }

  std::map<std::filesystem::path, std::map<std::string, std::string>> descriptions;  // per folder
  auto labels_for = [&](const std::filesystem::path& file) {
    ClipLabels labels = ParseClipLabels(file.filename().string());
    const std::filesystem::path folder = file.parent_path();
    if (!descriptions.contains(folder)) descriptions[folder] = ReadTrialDescriptions(folder / "cmu-descriptions.csv");
    const std::string key = TrialKey(labels);
    if (auto it = descriptions[folder].find(key); !key.empty() && it != descriptions[folder].end()) {
      labels.emplace_back("description", it->second);
    }
    return labels;
  };

  ImportSummary summary;
  summary.database = options.database;
  summary.rig_source = rig_source;
  summary.files = static_cast<int>(files.size());
  auto fill = [&](const ImportTotals& totals) {
    summary.created_database = totals.created_database;
    summary.imported = totals.imported;
    summary.duplicates = totals.duplicates;
    summary.failed = totals.failed;
    summary.frames = totals.frames;
    summary.source_frames = totals.source_frames;
    summary.motion_seconds = totals.motion_seconds;
  };
  const int threads = options.threads > 0 ? options.threads : std::max(1u, std::thread::hardware_concurrency());
  PreparePipeline pipeline(files, *writer->rig(), writer->preprocess(), threads);
  for (size_t i = 0; i < files.size(); ++i) {
    PreparedFile prepared = pipeline.Take(i);
    ClipLabels labels = prepared.status.ok() ? labels_for(files[i]) : ClipLabels{};
    MOCAP_RETURN_IF_ERROR(writer->Add(files[i].filename().string(), std::move(prepared), std::move(labels)));
    fill(writer->totals());
    if (progress) progress(static_cast<int>(i + 1), static_cast<int>(files.size()), summary);
  }
  MOCAP_RETURN_IF_ERROR(writer->Finish());
  fill(writer->totals());
  for (const ImportFileResult& file : writer->totals().files) {
    if (file.outcome == ImportFileResult::Outcome::kDuplicate)
      summary.problems.push_back(StrCat(file.file_name, ": ", file.message));
    if (file.outcome == ImportFileResult::Outcome::kFailed) summary.problems.push_back(file.message);
  }
  summary.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

}  // namespace mocap

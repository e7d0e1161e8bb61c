#include "server/import_command.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <thread>

#include <spdlog/spdlog.h>
#include <xxhash.h>

#include "motion/bvh/bvh_reader.h"
#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"
#include "motion/preprocess/clip_labels.h"
#include "motion/preprocess/clip_preprocessor.h"
#include "storage/motion_store.h"

namespace mocap {
namespace {

struct ParsedFile {
  absl::Status status = absl::OkStatus();
  std::string hash;
  BvhClip clip;
};

absl::StatusOr<std::string> ReadFileBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return absl::NotFoundError(StrCat(path.string(), ": cannot open file"));
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) return absl::DataLossError(StrCat(path.string(), ": read failed"));
  return bytes;
}

std::string ContentHash(const std::string& bytes) {
  const XXH128_hash_t hash = XXH3_128bits(bytes.data(), bytes.size());
  char text[33];
  std::snprintf(text, sizeof(text), "%016llx%016llx", static_cast<unsigned long long>(hash.high64),
                static_cast<unsigned long long>(hash.low64));
  return text;
}

ParsedFile ParseFile(const std::filesystem::path& path) {
  ParsedFile parsed;
  absl::StatusOr<std::string> bytes = ReadFileBytes(path);
  if (!bytes.ok()) {
    parsed.status = bytes.status();
    return parsed;
  }
  parsed.hash = ContentHash(*bytes);
  absl::StatusOr<BvhClip> clip = ParseBvh(*bytes, path.string());
  if (!clip.ok()) {
    parsed.status = clip.status();
  } else {
    parsed.clip = std::move(*clip);
  }
  return parsed;
}

struct PreparedFile {
  absl::Status status = absl::OkStatus();
  std::string hash;
  PreparedClip clip;
};

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
      std::lock_guard lock(mutex_);
      stopping_ = true;
    }
    changed_.notify_all();
    for (std::thread& worker : workers_) worker.join();
  }
  PreparedFile Take(size_t index) {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return results_[index].has_value(); });
    PreparedFile out = std::move(*results_[index]);
    results_[index].reset();
    consumed_ = index + 1;
    changed_.notify_all();
    return out;
  }

 private:
  void Work() {
    while (true) {
      size_t index;
      {
        std::unique_lock lock(mutex_);
        changed_.wait(lock, [&] { return stopping_ || next_ >= files_.size() || next_ < consumed_ + window_; });
        if (stopping_ || next_ >= files_.size()) return;
        index = next_++;
      }
      PreparedFile prepared;
      ParsedFile parsed = ParseFile(files_[index]);
      prepared.hash = parsed.hash;
      prepared.status = parsed.status;
      if (prepared.status.ok()) {
        absl::StatusOr<PreparedClip> clip = PrepareClip(parsed.clip, rig_, options_);
        if (clip.ok()) {
          prepared.clip = std::move(*clip);
        } else {
          prepared.status = absl::Status(clip.status().code(), StrCat(files_[index].string(), ": ", clip.status().message()));
        }
      }
      {
        std::lock_guard lock(mutex_);
        results_[index] = std::move(prepared);
      }
      changed_.notify_all();
    }
  }

  const std::vector<std::filesystem::path>& files_;
  const RigModel& rig_;
  const PreprocessOptions options_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<std::optional<PreparedFile>> results_;
  size_t next_ = 0;
  size_t consumed_ = 0;
  size_t window_ = 8;
  bool stopping_ = false;
  std::vector<std::thread> workers_;
};

}  // namespace

absl::StatusOr<std::vector<std::filesystem::path>> CollectBvhFiles(const std::vector<std::string>& inputs) {
  std::vector<std::filesystem::path> files;
  for (const std::string& input : inputs) {
    std::error_code error;
    const std::filesystem::path path(input);
    if (std::filesystem::is_directory(path, error)) {
      for (auto it = std::filesystem::recursive_directory_iterator(path, error);
           !error && it != std::filesystem::recursive_directory_iterator(); it.increment(error)) {
        std::string extension = it->path().extension().string();
        std::transform(extension.begin(), extension.end(), extension.begin(), ::tolower);
        if (it->is_regular_file() && extension == ".bvh") files.push_back(it->path());
      }
      if (error) return absl::InvalidArgumentError(StrCat(input, ": ", error.message()));
    } else if (std::filesystem::is_regular_file(path, error)) {
      files.push_back(path);
    } else {
      return absl::InvalidArgumentError(StrCat(input, ": no such file or folder"));
    }
  }
  if (files.empty()) return absl::InvalidArgumentError("no .bvh files found in the given inputs");
  std::sort(files.begin(), files.end());
  files.erase(std::unique(files.begin(), files.end()), files.end());
  return files;
}

absl::StatusOr<ImportSummary> RunImport(const ImportOptions& options, const ImportProgress& progress) {
  const auto start = std::chrono::steady_clock::now();
  MOCAP_ASSIGN_OR_RETURN(std::vector<std::filesystem::path> files, CollectBvhFiles(options.inputs));
  MOCAP_ASSIGN_OR_RETURN(std::unique_ptr<MotionStore> store, MotionStore::Open(options.store));

  ImportSummary summary;
  summary.database = options.database;
  summary.files = static_cast<int>(files.size());
  PreprocessOptions preprocess{.frame_rate = options.frame_rate, .unit = options.unit};

  // The database's rig: stored, or taken from the first file that reads (database created with
  // the first batch, so a failed first batch leaves no empty database behind).
  std::optional<DatabaseSummary> database;
  RigModel rig;
  if (absl::StatusOr<DatabaseSummary> found = store->FindDatabase(options.database); found.ok()) {
    database = *found;
    if (std::abs(options.frame_rate - found->frame_rate) > 1e-9) {
      spdlog::warn("database '{}' keeps its {} fps; --frame-rate {} applies only when a database is created",
                   options.database, found->frame_rate, options.frame_rate);
    }
    preprocess.frame_rate = found->frame_rate;
    MOCAP_ASSIGN_OR_RETURN(rig, store->LoadRig(found->id));
  } else if (found.status().code() != absl::StatusCode::kNotFound) {
    return found.status();
  } else {
    absl::Status first_error = absl::OkStatus();
    bool have_rig = false;
    for (const auto& file : files) {
      ParsedFile parsed = ParseFile(file);
      absl::StatusOr<RigModel> built = parsed.status.ok() ? BuildRigModel(parsed.clip, preprocess) : parsed.status;
      if (built.ok()) {
        rig = std::move(*built);
        have_rig = true;
        break;
      }
      const absl::Status error = parsed.status.ok()
                                     ? absl::Status(built.status().code(), StrCat(file.string(), ": ", built.status().message()))
                                     : parsed.status;
      if (!options.keep_going) return error;
      if (first_error.ok()) first_error = error;
    }
    if (!have_rig) return first_error;
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

  const int threads = options.threads > 0 ? options.threads : std::max(1u, std::thread::hardware_concurrency());
  PreparePipeline pipeline(files, rig, preprocess, threads);
  const size_t batch_size = options.batch_size > 0 ? static_cast<size_t>(options.batch_size) : files.size();
  int committed_batches = 0;
  std::unique_ptr<MotionStore::WriteBatch> batch;
  std::set<std::string> hashes_in_batch;
  ImportSummary committed = summary;  // what has been committed so far
  for (size_t i = 0; i < files.size(); ++i) {
    if (!batch) {
      MOCAP_ASSIGN_OR_RETURN(batch, store->BeginWrite());
      hashes_in_batch.clear();
    }
    PreparedFile prepared = pipeline.Take(i);
    const std::string name = files[i].filename().string();
    absl::Status status = prepared.status;
    if (status.ok() && !database) {
      // Created with its first clip, inside that clip's batch: a failed or empty import leaves
      // no empty database behind.
      MOCAP_ASSIGN_OR_RETURN(DatabaseSummary created, store->CreateDatabase(options.database, rig, preprocess.frame_rate));
      database = created;
      summary.created_database = true;
    }
    if (status.ok()) {
      MOCAP_ASSIGN_OR_RETURN(std::optional<std::int64_t> existing, store->FindClipByHash(database->id, prepared.hash));
      if (existing || hashes_in_batch.contains(prepared.hash)) {
        ++summary.duplicates;
        summary.problems.push_back(StrCat(files[i].string(), ": already imported",
                                          existing ? StrCat(" as clip ", *existing) : std::string(" (same content earlier in this import)")));
      } else {
        absl::StatusOr<std::int64_t> id =
            store->InsertClip(database->id, name, prepared.hash, labels_for(files[i]), prepared.clip, rig);
        if (!id.ok()) return id.status();
        hashes_in_batch.insert(prepared.hash);
        ++summary.imported;
        summary.frames += prepared.clip.num_frames();
        summary.source_frames += prepared.clip.source_frames;
        summary.motion_seconds += prepared.clip.num_frames() / preprocess.frame_rate;
      }
    } else if (options.keep_going) {
      ++summary.failed;
      summary.problems.push_back(std::string(status.message()));
    } else {
      batch.reset();  // roll back this batch
      std::string message = StrCat(status.message(), " — nothing from this batch was stored");
      if (committed_batches > 0) {
        message += StrCat(" (", committed_batches, " earlier batch(es) with ", committed.imported, " clips were kept)");
      }
      return absl::Status(status.code(), message);
    }
    const bool batch_full = (i + 1) % batch_size == 0 || i + 1 == files.size();
    if (batch_full) {
      MOCAP_RETURN_IF_ERROR(batch->Commit());
      batch.reset();
      ++committed_batches;
      committed = summary;
    }
    if (progress) progress(static_cast<int>(i + 1), static_cast<int>(files.size()), summary);
  }
  summary.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

}  // namespace mocap

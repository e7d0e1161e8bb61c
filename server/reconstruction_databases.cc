#include "server/reconstruction_databases.h"

#include <chrono>
#include <functional>

#include <spdlog/spdlog.h>

#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"

namespace mocap {

ReconstructionDatabases::ReconstructionDatabases(StorePool& stores, int max_cached)
    : stores_(stores), max_cached_(std::max(1, max_cached)) {}

ReconstructionDatabases::~ReconstructionDatabases() {
  std::list<Builder> builders;
  {
    std::lock_guard lock(mutex_);
    builders.swap(builders_);
  }
  for (Builder& builder : builders) builder.thread.join();
}

int ReconstructionDatabases::builds() const {
  std::lock_guard lock(mutex_);
  return builds_;
}

absl::StatusOr<std::string> ReconstructionDatabases::ContentStamp(MotionStore& store, std::int64_t database_id) {
  MOCAP_ASSIGN_OR_RETURN(std::vector<ClipSummary> clips, store.ListClips(database_id));
  // Ids alone could repeat after a delete and an import; the content hashes cannot.
  std::size_t hash = std::hash<std::int64_t>()(database_id);
  for (const ClipSummary& clip : clips) {
    hash = hash * 1000003u ^ std::hash<std::int64_t>()(clip.id);
    hash = hash * 1000003u ^ std::hash<std::string>()(clip.content_hash);
  }
  return StrCat(clips.size(), "-", hash);
}

absl::StatusOr<ReconstructionDatabases::Database> ReconstructionDatabases::Load(MotionStore& store, const Key& key) {
  MOCAP_ASSIGN_OR_RETURN(RigModel rig, store.LoadRig(key.database_id));
  MOCAP_ASSIGN_OR_RETURN(std::vector<ClipSummary> summaries, store.ListClips(key.database_id));
  if (summaries.empty()) return absl::FailedPreconditionError("the database has no clips: import motion into it first");
  std::vector<DatabaseClip> clips;
  clips.reserve(summaries.size());
  for (const ClipSummary& summary : summaries) {
    MOCAP_ASSIGN_OR_RETURN(StoredClip clip, store.LoadClip(summary.id, rig));
    clips.push_back({std::move(clip.features), EncodePoses(clip.motion, rig)});
  }
  const double frame_rate = key.frame_rate > 0 ? key.frame_rate : 30.0;
  return ReconstructionDatabase::Build(rig, clips, 0.8f, 1.0 / frame_rate);
}

void ReconstructionDatabases::Acquire(const Key& key, Ready ready) {
  std::unique_lock lock(mutex_);
  ReapBuilders();
  Entry& entry = entries_[{key.database_id, key.content_stamp}];
  entry.last_used = ++clock_;
  if (entry.database) {
    Database database = entry.database;
    lock.unlock();
    ready(std::move(database));
    return;
  }
  entry.waiting.push_back(std::move(ready));
  if (entry.building) return;
  entry.building = true;
  Builder& builder = builders_.emplace_back();
  builder.thread = std::thread([this, key, &builder] { Build(key, &builder); });
}

void ReconstructionDatabases::Build(Key key, Builder* self) {
  const auto start = std::chrono::steady_clock::now();
  absl::StatusOr<Database> built = [&]() -> absl::StatusOr<Database> {
    MOCAP_ASSIGN_OR_RETURN(StorePool::Lease store, stores_.Acquire());
    try {
      return Load(*store, key);
    } catch (const std::exception& error) {  // SQLiteCpp throws on broken files
      return absl::InternalError(StrCat("building the reconstruction database: ", error.what()));
    }
  }();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (built.ok()) {
    spdlog::info("reconstruction database {} built: {} frames in {:.1f} s", key.database_id, (*built)->num_frames(), seconds);
  } else {
    spdlog::warn("reconstruction database {} failed to build: {}", key.database_id, built.status().ToString());
  }
  std::vector<Ready> waiting;
  {
    std::lock_guard lock(mutex_);
    const EntryKey entry_key{key.database_id, key.content_stamp};
    Entry& entry = entries_[entry_key];
    waiting.swap(entry.waiting);
    entry.building = false;
    if (built.ok()) {
      entry.database = *built;
      ++builds_;
      // Older versions of this database are not needed by new sessions (running ones hold theirs).
      for (auto it = entries_.begin(); it != entries_.end();) {
        const bool older = it->first.first == key.database_id && it->first != entry_key && !it->second.building;
        it = older ? entries_.erase(it) : std::next(it);
      }
      Evict();
    } else {
      entries_.erase(entry_key);  // the next session tries again
    }
  }
  for (Ready& ready : waiting) ready(built);
  std::lock_guard lock(mutex_);
  self->done = true;  // nothing left to run: ReapBuilders (or the destructor) joins the thread
}

void ReconstructionDatabases::Evict() {
  int cached = 0;
  for (const auto& [key, entry] : entries_) cached += entry.database ? 1 : 0;
  while (cached > max_cached_) {
    auto oldest = entries_.end();
    for (auto it = entries_.begin(); it != entries_.end(); ++it) {
      if (it->second.database && (oldest == entries_.end() || it->second.last_used < oldest->second.last_used)) oldest = it;
    }
    entries_.erase(oldest);
    --cached;
  }
}

void ReconstructionDatabases::ReapBuilders() {
  for (auto it = builders_.begin(); it != builders_.end();) {
    if (!it->done) {
      ++it;
      continue;
    }
    it->thread.join();
    it = builders_.erase(it);
  }
}

}  // namespace mocap

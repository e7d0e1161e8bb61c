#include "server/version_registry.h"

#include <chrono>
#include <exception>
#include <functional>

#include <spdlog/spdlog.h>

#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"
#include "server/work_pool.h"

namespace mocap {

VersionRegistry::VersionRegistry(StorePool& stores, int max_cached, std::string what, Loader loader)
    : stores_(stores), max_cached_(std::max(1, max_cached)), what_(std::move(what)), loader_(std::move(loader)) {}

VersionRegistry::~VersionRegistry() { WaitForBuilds(); }

void VersionRegistry::WaitForBuilds() {
  std::list<Builder> builders;
  {
    MutexLock lock(&mutex_);
    builders.swap(builders_);
  }
  for (Builder& builder : builders) builder.thread.join();
}

int VersionRegistry::builds() const {
  MutexLock lock(&mutex_);
  return builds_;
}

void VersionRegistry::Acquire(const DatabaseVersion& version, Ready ready) {
  Value value;
  {
    MutexLock lock(&mutex_);
    ReapBuilders();
    Entry& entry = entries_[{version.database.id(), version.variant, version.content_stamp}];
    entry.last_used = ++clock_;
    if (!entry.value) {
      entry.waiting.push_back(std::move(ready));
      if (entry.building) return;
      entry.building = true;
      Builder& builder = builders_.emplace_back();
      builder.thread = std::thread([this, version, &builder] { Build(version, &builder); });
      return;
    }
    value = entry.value;
  }
  ready(std::move(value));  // outside the lock: it may call back into the registry
}

void VersionRegistry::Build(DatabaseVersion version, Builder* self) {
  // Seconds of one tenant's CPU (a 306k-frame database's trees): bulk work, below every other
  // tenant's live sessions, as imports are; it ran at gRPC's priority, above the compute pool
  // (beside benchmarks/fairness_flood.sh's `rebuilds` the difference was within the noise).
  RunThisThreadAt(WorkPool::Priority::kBulk);
  const auto start = std::chrono::steady_clock::now();
  absl::StatusOr<Value> built = [&]() -> absl::StatusOr<Value> {
    MOCAP_ASSIGN_OR_RETURN(StorePool::Lease store, stores_.Acquire());
    try {
      return loader_(*store, version);
    } catch (const std::exception& error) {  // SQLiteCpp throws on broken files
      return absl::InternalError(StrCat("building the ", what_, ": ", error.what()));
    }
  }();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::string variant = version.variant.empty() ? "" : StrCat(" (", version.variant, ")");
  if (built.ok()) {
    spdlog::info("{} of database {}{} built in {:.1f} s", what_, version.database.id(), variant, seconds);
  } else {
    spdlog::warn("{} of database {}{} failed to build: {}", what_, version.database.id(), variant,
                 built.status().ToString());
  }
  std::vector<Ready> waiting;
  {
    MutexLock lock(&mutex_);
    const EntryKey entry_key{version.database.id(), version.variant, version.content_stamp};
    Entry& entry = entries_[entry_key];
    waiting.swap(entry.waiting);
    entry.building = false;
    if (built.ok()) {
      entry.value = *built;
      ++builds_;
      // Older versions of this database are not needed by new calls (running ones hold theirs).
      for (auto it = entries_.begin(); it != entries_.end();) {
        const bool older = it->first.database_id == version.database.id() && it->first.variant == version.variant &&
                           it->first != entry_key && !it->second.building;
        it = older ? entries_.erase(it) : std::next(it);
      }
      Evict();
    } else {
      entries_.erase(entry_key);  // the next call tries again
    }
  }
  for (Ready& ready : waiting) ready(built);
  MutexLock lock(&mutex_);
  self->done = true;  // nothing left to run: ReapBuilders (or the destructor) joins the thread
}

void VersionRegistry::Evict() {
  int cached = 0;
  for (const auto& [key, entry] : entries_) cached += entry.value ? 1 : 0;
  while (cached > max_cached_) {
    auto oldest = entries_.end();
    for (auto it = entries_.begin(); it != entries_.end(); ++it) {
      if (it->second.value && (oldest == entries_.end() || it->second.last_used < oldest->second.last_used))
        oldest = it;
    }
    entries_.erase(oldest);
    --cached;
  }
}

void VersionRegistry::ReapBuilders() {
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

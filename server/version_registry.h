// VersionRegistry: the query-ready form of each store database version (reconstruction indices,
// pose-search indices), built from the store when a call first needs it and then shared
// read-only by every call on that version. What is built is up to the loader: one registry per
// kind of index, each with the same caching rules.
//
// An entry is keyed by the database's content stamp (its clips' ids and content hashes), so an
// import or a deletion makes the next call rebuild, while calls already running keep the
// version they started with (shared ownership). Builds run on their own threads, one per
// database version at a time; callers wait through a callback, so no gRPC or worker thread
// blocks. At most `max_cached` idle versions are kept (least recently used dropped first).
//
// Thread safety: all methods are thread-safe.
#pragma once

#include <cstdint>
#include <functional>
#include <list>
#include <map>
#include <memory>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "absl/status/statusor.h"
#include "motion/core/mutex.h"
#include "server/store_pool.h"

namespace mocap {

// One version of a store database: what a registry entry is built from and keyed by.
struct DatabaseVersion {
  DatabaseRef database;       // its id is part of the key; its name is for what is built
  std::string content_stamp;  // MotionStore::ContentStamp()
  double frame_rate = 30.0;
  // Which form of the database is built, when a registry builds several (the pose index's point
  // options); part of the key. A new content stamp replaces the older entries of the same variant.
  std::string variant;
};

class VersionRegistry {
 public:
  using Value = std::shared_ptr<const void>;
  using Ready = std::function<void(absl::StatusOr<Value>)>;
  // Builds one version from the store (runs on a builder thread; may throw: caught, INTERNAL).
  using Loader = std::function<absl::StatusOr<Value>(MotionStore& store, const DatabaseVersion& version)>;

  // `what` names the built thing in the server log ("reconstruction database", "pose index").
  VersionRegistry(StorePool& stores, int max_cached, std::string what, Loader loader);
  // Waits for the builds in progress (their callers get their callbacks).
  ~VersionRegistry();
  VersionRegistry(const VersionRegistry&) = delete;
  VersionRegistry& operator=(const VersionRegistry&) = delete;

  // Calls `ready` exactly once: at once (on this thread) when the version is built, otherwise on
  // the builder thread when it is.
  void Acquire(const DatabaseVersion& version, Ready ready);

  int builds() const;  // versions built so far (for tests and metrics)
  // Joins the builds in progress (their callers get their callbacks): for an owner whose
  // callbacks use what it destroys before this registry.
  void WaitForBuilds();

 private:
  struct Entry {
    Value value;                 // set when built
    std::vector<Ready> waiting;  // callers while building
    bool building = false;
    std::uint64_t last_used = 0;
  };
  struct EntryKey {
    std::int64_t database_id;
    std::string variant;
    std::string content_stamp;
    auto operator<=>(const EntryKey&) const = default;
  };
  struct Builder {
    std::thread thread;
    bool done = false;
  };
  void Build(DatabaseVersion version, Builder* self);
  void Evict() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  void ReapBuilders() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);  // joins finished builder threads

  StorePool& stores_;
  const int max_cached_;
  const std::string what_;
  const Loader loader_;
  mutable Mutex mutex_;
  std::map<EntryKey, Entry> entries_ ABSL_GUARDED_BY(mutex_);
  std::list<Builder> builders_ ABSL_GUARDED_BY(mutex_);
  std::uint64_t clock_ ABSL_GUARDED_BY(mutex_) = 0;
  int builds_ ABSL_GUARDED_BY(mutex_) = 0;
};

// A registry of one value type T (a thin typed view of VersionRegistry).
template <typename T>
class TypedVersionRegistry {
 public:
  using Value = std::shared_ptr<const T>;
  using Ready = std::function<void(absl::StatusOr<Value>)>;
  using Loader = std::function<absl::StatusOr<Value>(MotionStore& store, const DatabaseVersion& version)>;

  TypedVersionRegistry(StorePool& stores, int max_cached, std::string what, Loader loader)
      : registry_(stores, max_cached, std::move(what),
                  [loader = std::move(loader)](
                      MotionStore& store, const DatabaseVersion& version) -> absl::StatusOr<VersionRegistry::Value> {
                    absl::StatusOr<Value> value = loader(store, version);
                    if (!value.ok()) return value.status();
                    return VersionRegistry::Value(std::move(*value));
                  }) {}

  void Acquire(const DatabaseVersion& version, Ready ready) {
    registry_.Acquire(version, [ready = std::move(ready)](absl::StatusOr<VersionRegistry::Value> value) {
      if (!value.ok()) return ready(value.status());
      ready(std::static_pointer_cast<const T>(std::move(*value)));
    });
  }
  int builds() const { return registry_.builds(); }
  void WaitForBuilds() { registry_.WaitForBuilds(); }

 private:
  VersionRegistry registry_;
};

}  // namespace mocap

// ReconstructionDatabases: the query-ready form of each store database (ReconstructionDatabase:
// A1 features, pose features and the kd-trees of METHOD.md A3/A5), built from the store when a
// session first needs it and then shared read-only by every session on that database.
//
// An entry is keyed by the database's content stamp (its clips' ids and content hashes), so an
// import or a deletion makes the next session rebuild, while sessions already running keep the
// version they started with (shared ownership). Builds run on their own threads, one per
// database at a time; callers wait through a callback, so no gRPC or worker thread blocks.
// At most `max_cached` idle versions are kept (least recently used dropped first).
//
// Thread safety: all methods are thread-safe.
#pragma once

#include <cstdint>
#include <functional>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "absl/status/statusor.h"
#include "motion/reconstruct/reconstruction_database.h"
#include "server/store_pool.h"

namespace mocap {

class ReconstructionDatabases {
 public:
  using Database = std::shared_ptr<const ReconstructionDatabase>;
  using Ready = std::function<void(absl::StatusOr<Database>)>;

  ReconstructionDatabases(StorePool& stores, int max_cached);
  // Waits for the builds in progress (their callers get their callbacks).
  ~ReconstructionDatabases();
  ReconstructionDatabases(const ReconstructionDatabases&) = delete;
  ReconstructionDatabases& operator=(const ReconstructionDatabases&) = delete;

  struct Key {
    std::int64_t database_id = 0;
    std::string content_stamp;  // ContentStamp()
    double frame_rate = 30.0;
  };
  // Calls `ready` exactly once: at once (on this thread) when the version is built, otherwise on
  // the builder thread when it is. FailedPrecondition for a database without clips.
  void Acquire(const Key& key, Ready ready);

  // The content stamp of a database now (one query on `store`).
  static absl::StatusOr<std::string> ContentStamp(MotionStore& store, std::int64_t database_id);
  // Builds one database from the store (what a builder thread runs).
  static absl::StatusOr<Database> Load(MotionStore& store, const Key& key);

  int builds() const;  // versions built so far (for tests and metrics)

 private:
  struct Entry {
    Database database;           // set when built
    std::vector<Ready> waiting;  // callers while building
    bool building = false;
    std::uint64_t last_used = 0;
  };
  using EntryKey = std::pair<std::int64_t, std::string>;  // database id, content stamp
  struct Builder {
    std::thread thread;
    bool done = false;
  };
  void Build(Key key, Builder* self);
  void Evict();          // with mutex_ held
  void ReapBuilders();   // with mutex_ held: joins finished builder threads

  StorePool& stores_;
  const int max_cached_;
  mutable std::mutex mutex_;
  std::map<EntryKey, Entry> entries_;
  std::list<Builder> builders_;
  std::uint64_t clock_ = 0;
  int builds_ = 0;
};

}  // namespace mocap

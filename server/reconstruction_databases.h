// ReconstructionDatabases: the query-ready form of each store database (ReconstructionDatabase:
// A1 features, pose features and the kd-trees of docs/method.md A3/A5), built from the store when a
// session first needs it and then shared read-only by every session on that database; an import
// or a deletion makes the next session use a rebuilt version (caching rules: VersionRegistry).
//
// Thread safety: all methods are thread-safe.
#pragma once

#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "motion/reconstruct/reconstruction_database.h"
#include "server/version_registry.h"

namespace mocap {

class ReconstructionDatabases {
 public:
  using Database = std::shared_ptr<const ReconstructionDatabase>;
  using Ready = std::function<void(absl::StatusOr<Database>)>;
  using Key = DatabaseVersion;

  ReconstructionDatabases(StorePool& stores, int max_cached, bool time_reversed_copies = true)
      : registry_(stores, max_cached, "reconstruction database",
                  [time_reversed_copies](MotionStore& store, const Key& key) {
                    return Load(store, key, time_reversed_copies);
                  }) {}

  // Calls `ready` exactly once: at once (on this thread) when the version is built, otherwise on
  // the builder thread when it is. FailedPrecondition for a database without clips.
  void Acquire(const Key& key, Ready ready) { registry_.Acquire(key, std::move(ready)); }

  // Builds one database from the store (what a builder thread runs), with its travelling frames
  // also played backwards unless told not to (DatabaseBuildOptions).
  static absl::StatusOr<Database> Load(MotionStore& store, const Key& key, bool time_reversed_copies = true);

  int builds() const { return registry_.builds(); }    // versions built so far (for tests and metrics)
  void WaitForBuilds() { registry_.WaitForBuilds(); }  // VersionRegistry::WaitForBuilds

 private:
  TypedVersionRegistry<ReconstructionDatabase> registry_;
};

}  // namespace mocap

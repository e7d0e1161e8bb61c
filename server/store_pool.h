// StorePool: reusable MotionStore connections to one store file. A MotionStore is one SQLite
// connection for one thread at a time; each request leases one, so requests run in parallel and
// (WAL mode) an import's write never blocks readers.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <vector>

#include "absl/status/statusor.h"
#include "motion/core/mutex.h"
#include "storage/motion_store.h"

namespace mocap {

class StorePool {
 public:
  // A leased connection; returned to the pool when destroyed.
  using Lease = std::unique_ptr<MotionStore, std::function<void(MotionStore*)>>;

  // Opens (creating and migrating when missing) the store once, to fail early. With `read_only`
  // every connection is read-only and immutable (StoreOpenOptions): the file must exist.
  static absl::StatusOr<std::unique_ptr<StorePool>> Open(const std::filesystem::path& path, bool read_only = false);
  bool read_only() const { return read_only_; }

  // Thread-safe. An idle connection, or a new one.
  absl::StatusOr<Lease> Acquire();

 private:
  StorePool(std::filesystem::path path, bool read_only) : path_(std::move(path)), read_only_(read_only) {}
  StoreOpenOptions Options() const {
    return {.create_if_missing = false, .read_only = read_only_, .immutable = read_only_};
  }
  std::filesystem::path path_;
  bool read_only_ = false;
  Mutex mutex_;
  std::vector<std::unique_ptr<MotionStore>> idle_ ABSL_GUARDED_BY(mutex_);
};

}  // namespace mocap

// StorePool: reusable MotionStore connections to one store file. A MotionStore is one SQLite
// connection for one thread at a time; each request leases one, so requests run in parallel and
// (WAL mode) an import's write never blocks readers.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <vector>

#include "absl/status/statusor.h"
#include "storage/motion_store.h"

namespace mocap {

class StorePool {
 public:
  // A leased connection; returned to the pool when destroyed.
  using Lease = std::unique_ptr<MotionStore, std::function<void(MotionStore*)>>;

  // Opens (creating and migrating when missing) the store once, to fail early.
  static absl::StatusOr<std::unique_ptr<StorePool>> Open(const std::filesystem::path& path);

  // Thread-safe. An idle connection, or a new one.
  absl::StatusOr<Lease> Acquire();

 private:
  explicit StorePool(std::filesystem::path path) : path_(std::move(path)) {}
  std::filesystem::path path_;
  std::mutex mutex_;
  std::vector<std::unique_ptr<MotionStore>> idle_;
};

}  // namespace mocap

// MotionStore: one SQLite file holding many motion databases (one rig each) and their clips.
//
// Thread safety: a MotionStore is one connection; use it from one thread at a time. Several
// processes may open the same file (WAL mode); writers are serialised by SQLite.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "motion/preprocess/clip_labels.h"
#include "motion/preprocess/clip_preprocessor.h"

namespace SQLite {
class Database;
class Statement;
class Transaction;
}  // namespace SQLite

namespace mocap {

// Every database belongs to a tenant (storage/tenant_directory.h); names are unique per tenant.
using TenantId = std::int64_t;
// The tenant of databases from version 1 stores, and the one the local admin commands act as.
inline constexpr TenantId kDefaultTenantId = 1;

class MotionStore;

// One tenant's database as that tenant's lookup found it: the key every call that reads or
// writes a database's rig and clips takes. Only MotionStore makes one (FindDatabase,
// ListDatabases, Create*), so no bare id — from a request, from another tenant's lookup — can
// reach those calls; and ids are never reused (schema 3), so a ref that outlives its database
// (an open import, a cached index) answers NotFound and never lands in another's database.
// A default ref names no database.
class DatabaseRef {
 public:
  DatabaseRef() = default;
  std::int64_t id() const { return id_; }
  TenantId tenant() const { return tenant_; }
  const std::string& name() const { return name_; }
  friend bool operator==(const DatabaseRef&, const DatabaseRef&) = default;

 private:
  friend class MotionStore;
  DatabaseRef(std::int64_t id, TenantId tenant, std::string name) : id_(id), tenant_(tenant), name_(std::move(name)) {}
  std::int64_t id_ = 0;
  TenantId tenant_ = kDefaultTenantId;
  std::string name_;
};

struct DatabaseSummary {
  DatabaseRef ref;
  double frame_rate = 0.0;
  bool has_rig = false;                       // false for a database created empty, until its first import
  LengthUnit unit = LengthUnit::kCentimetre;  // meaningful only with has_rig
  int num_joints = 0;
  std::string root_joint;
  std::int64_t num_clips = 0;
  std::int64_t num_frames = 0;
  double seconds() const { return frame_rate > 0 ? static_cast<double>(num_frames) / frame_rate : 0.0; }
};

struct ClipSummary {
  std::int64_t id = 0;
  std::string source_name;
  std::string content_hash;
  int num_frames = 0;
  double source_frame_rate = 0.0;
  int source_frames = 0;
  ClipLabels labels;
};

// A clip as stored: labels, this performer's skeleton (metres) and the decoded motion and
// features at the database rate.
struct StoredClip {
  ClipSummary summary;
  Skeleton skeleton;
  LocalMotion motion;
  std::vector<FrameFeatures> features;
};

struct StoreOpenOptions {
  bool create_if_missing = true;
  bool read_only = false;
  // With read_only: the file is promised not to change while open (SQLite's immutable=1): no
  // locks, no -wal/-shm files, so it opens on a read-only mount. FailedPrecondition when the
  // file has changes not yet checkpointed (a non-empty FILE-wal beside it).
  bool immutable = false;
};

// Database names: 1 to kMaxDatabaseNameBytes bytes (InvalidArgument otherwise).
inline constexpr size_t kMaxDatabaseNameBytes = 128;
absl::Status CheckDatabaseName(std::string_view name);

class MotionStore {
 public:
  // Opens (or creates, with its parent folder) the store file and migrates its schema.
  static absl::StatusOr<std::unique_ptr<MotionStore>> Open(const std::filesystem::path& path,
                                                           const StoreOpenOptions& options = {});
  ~MotionStore();
  MotionStore(const MotionStore&) = delete;
  MotionStore& operator=(const MotionStore&) = delete;

  const std::filesystem::path& path() const { return path_; }

  // All-or-nothing writes: everything between BeginWrite and Commit lands together or not at
  // all (also across a crash or kill -9). Destroying an uncommitted WriteBatch rolls it back.
  class WriteBatch {
   public:
    ~WriteBatch();
    absl::Status Commit();

   private:
    friend class MotionStore;
    explicit WriteBatch(std::unique_ptr<SQLite::Transaction> transaction);
    std::unique_ptr<SQLite::Transaction> transaction_;
  };
  absl::StatusOr<std::unique_ptr<WriteBatch>> BeginWrite();

  // Databases are looked up by name within one tenant (default: kDefaultTenantId); everything
  // else takes the DatabaseRef that lookup gave, and a clip id only within its database.

  // NotFound when the tenant has no database called `name`.
  absl::StatusOr<DatabaseSummary> FindDatabase(const std::string& name, TenantId tenant = kDefaultTenantId);
  absl::StatusOr<std::vector<DatabaseSummary>> ListDatabases(TenantId tenant = kDefaultTenantId);
  // AlreadyExists when the tenant has the name already; InvalidArgument for an empty or
  // over-long name or a frame rate outside (0, 1000].
  absl::StatusOr<DatabaseSummary> CreateDatabase(const std::string& name, const RigModel& rig, double frame_rate,
                                                 TenantId tenant = kDefaultTenantId);
  // A database without a rig yet: the first import fixes it (SetRig).
  absl::StatusOr<DatabaseSummary> CreateEmptyDatabase(const std::string& name, double frame_rate,
                                                      TenantId tenant = kDefaultTenantId);
  // FailedPrecondition when the database has a rig already.
  // Each call below answers NotFound when the database no longer exists.
  absl::Status SetRig(const DatabaseRef& database, const RigModel& rig);
  // FailedPrecondition when the database has no rig yet.
  absl::StatusOr<RigModel> LoadRig(const DatabaseRef& database);
  absl::Status DeleteDatabase(const DatabaseRef& database);
  // NotFound unless the database still exists as its tenant's database of that name: work that
  // outlives its lookup (an open import) checks it inside the write that depends on it.
  absl::Status CheckDatabaseExists(const DatabaseRef& database);

  // Id of the clip with this content hash in the database, if any.
  absl::StatusOr<std::optional<std::int64_t>> FindClipByHash(const DatabaseRef& database,
                                                             const std::string& content_hash);
  // Inserts one clip (with its labels); returns its id.
  absl::StatusOr<std::int64_t> InsertClip(const DatabaseRef& database, const std::string& source_name,
                                          const std::string& content_hash, const ClipLabels& labels,
                                          const PreparedClip& clip, const RigModel& rig);
  absl::StatusOr<std::vector<ClipSummary>> ListClips(const DatabaseRef& database);
  // A value that changes whenever the database's clips change (an import, a deletion, a deleted
  // clip's id reused by another file), for what is built from them (the server's indices).
  // Cached per connection until anything is committed to the file: SQLite's data_version tells
  // of commits by other connections or processes, the connection's change count of its own, so
  // a call costs two cheap look-ups while nothing changes (a listing of the clips otherwise).
  absl::StatusOr<std::string> ContentStamp(const DatabaseRef& database);
  // NotFound when the database has no clip with that id (labels not filled).
  absl::StatusOr<ClipSummary> FindClip(const DatabaseRef& database, std::int64_t clip_id);
  // NotFound when the database has no clip with that id.
  absl::Status DeleteClip(const DatabaseRef& database, std::int64_t clip_id);
  // NotFound when the database has no clip with that id; DataLoss when a blob does not have the
  // size its row declares.
  absl::StatusOr<StoredClip> LoadClip(const DatabaseRef& database, std::int64_t clip_id, const RigModel& rig);

 private:
  friend class TenantDirectory;  // tenants and keys share the connection
  MotionStore(std::filesystem::path path, std::unique_ptr<SQLite::Database> db);
  // A row of kSummarySelect (motion_store.cc); the one place a DatabaseRef is made.
  static absl::StatusOr<DatabaseSummary> SummaryFromRow(SQLite::Statement& query);
  absl::StatusOr<DatabaseSummary> InsertDatabase(TenantId tenant, const std::string& name, const RigModel* rig,
                                                 double frame_rate);
  std::filesystem::path path_;
  std::unique_ptr<SQLite::Database> db_;
  // ContentStamp's cache: valid while the file's data_version and this connection's change
  // count are what they were when it was filled.
  struct StampCache {
    std::int64_t data_version = -1;
    std::int64_t total_changes = -1;
    std::map<std::int64_t, std::string> stamps;
  };
  StampCache stamp_cache_;
};

}  // namespace mocap

#include "storage/motion_store.h"

#include <cstdlib>
#include <cstring>
#include <functional>

#include <SQLiteCpp/Database.h>
#include <SQLiteCpp/Statement.h>
#include <SQLiteCpp/Transaction.h>
#include <sqlite3.h>

#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"
#include "storage/rig_codec.h"
#include "storage/schema.h"
#include "storage/sqlite_status.h"

namespace mocap {
namespace {

using storage::FromException;

template <typename T>
void BindFloats(SQLite::Statement& statement, int index, const std::vector<T>& values) {
  statement.bind(index, static_cast<const void*>(values.data()), static_cast<int>(values.size() * sizeof(T)));
}

template <typename T>
absl::Status ReadFloats(const SQLite::Column& column, size_t expected_count, std::vector<T>& out,
                        std::string_view what) {
  const size_t bytes = static_cast<size_t>(column.getBytes());
  if (bytes != expected_count * sizeof(T)) {
    return absl::DataLossError(
        StrCat("clip ", what, " blob has ", bytes, " bytes; expected ", expected_count * sizeof(T)));
  }
  out.resize(expected_count);
  if (bytes > 0) std::memcpy(out.data(), column.getBlob(), bytes);
  return absl::OkStatus();
}

constexpr const char* kSummarySelect = R"sql(
  SELECT d.id, d.name, d.frame_rate, d.unit, d.rig, d.tenant_id,
         (SELECT COUNT(*) FROM clips c WHERE c.database_id = d.id),
         (SELECT COALESCE(SUM(num_frames), 0) FROM clips c WHERE c.database_id = d.id)
  FROM databases d)sql";

// The answer of every call whose database is gone: deleted, perhaps while the caller used it.
absl::Status NoLongerExists(const DatabaseRef& database) {
  return absl::NotFoundError(StrCat("motion database '", database.name(), "' no longer exists"));
}

// Columns: id, source_name, content_hash, num_frames, source_frame_rate, source_frames.
ClipSummary ClipFromRow(SQLite::Statement& query) {
  ClipSummary clip;
  clip.id = query.getColumn(0).getInt64();
  clip.source_name = query.getColumn(1).getString();
  clip.content_hash = query.getColumn(2).getString();
  clip.num_frames = query.getColumn(3).getInt();
  clip.source_frame_rate = query.getColumn(4).getDouble();
  clip.source_frames = query.getColumn(5).getInt();
  return clip;
}

// SQLite URI of `path` opened immutable (RFC 3986 escapes for the characters URIs reserve).
std::string ImmutableUri(const std::filesystem::path& path) {
  std::string uri = "file:";
  for (const char c : std::filesystem::absolute(path).string()) {
    if (c == '%' || c == '?' || c == '#' || c == ' ') {
      static const char* hex = "0123456789ABCDEF";
      uri += '%';
      uri += hex[(c >> 4) & 0xF];
      uri += hex[c & 0xF];
    } else {
      uri += c;
    }
  }
  return uri + "?immutable=1";
}

// An immutable open ignores the WAL: changes still in it would be invisible.
absl::Status CheckCheckpointed(const std::filesystem::path& path) {
  std::error_code error;
  const std::filesystem::path wal = path.string() + "-wal";
  if (std::filesystem::exists(wal, error) && std::filesystem::file_size(wal, error) > 0) {
    return absl::FailedPreconditionError(StrCat(path.string(), " has changes not yet checkpointed into it (",
                                                wal.string(),
                                                "); stop its writers, or copy it with sqlite3's .backup, first"));
  }
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<DatabaseSummary> MotionStore::SummaryFromRow(SQLite::Statement& query) {
  DatabaseSummary summary;
  summary.ref =
      DatabaseRef(query.getColumn(0).getInt64(), query.getColumn(5).getInt64(), query.getColumn(1).getString());
  summary.frame_rate = query.getColumn(2).getDouble();
  summary.num_clips = query.getColumn(6).getInt64();
  summary.num_frames = query.getColumn(7).getInt64();
  summary.has_rig = !query.getColumn(4).isNull();
  if (!summary.has_rig) return summary;
  auto unit = ParseUnit(query.getColumn(3).getString());
  if (!unit) return absl::DataLossError("database has an unknown unit");
  summary.unit = *unit;
  MOCAP_ASSIGN_OR_RETURN(RigModel rig, storage::DecodeRig(query.getColumn(4).getString()));
  summary.num_joints = rig.skeleton.num_joints();
  summary.root_joint = rig.skeleton.joint(0).name;
  return summary;
}

MotionStore::MotionStore(std::filesystem::path path, std::unique_ptr<SQLite::Database> db)
    : path_(std::move(path)), db_(std::move(db)) {}
MotionStore::~MotionStore() = default;

absl::StatusOr<std::unique_ptr<MotionStore>> MotionStore::Open(const std::filesystem::path& path,
                                                               const StoreOpenOptions& options) {
  try {
    if (!options.read_only && options.create_if_missing && path.has_parent_path()) {
      std::error_code error;
      std::filesystem::create_directories(path.parent_path(), error);
    }
    if (!options.create_if_missing && !std::filesystem::exists(path)) {
      return absl::NotFoundError(StrCat("no motion store at ", path.string()));
    }
    int flags = options.read_only ? SQLite::OPEN_READONLY : SQLite::OPEN_READWRITE;
    if (options.create_if_missing && !options.read_only) flags |= SQLite::OPEN_CREATE;
    std::string name = path.string();
    if (options.read_only && options.immutable) {
      MOCAP_RETURN_IF_ERROR(CheckCheckpointed(path));
      name = ImmutableUri(path);
      flags |= SQLite::OPEN_URI;
    }
    auto db = std::make_unique<SQLite::Database>(name, flags, /*busy_timeout_ms=*/10000);
    db->exec("PRAGMA foreign_keys = ON");
    if (!options.read_only) {
      db->exec("PRAGMA journal_mode = WAL");
      db->exec("PRAGMA synchronous = NORMAL");  // WAL + NORMAL: durable across process crashes
      MOCAP_RETURN_IF_ERROR(storage::MigrateSchema(*db));
    } else if (const int version = storage::SchemaVersion(*db);
               version < storage::kMinReadOnlySchemaVersion || version > storage::kSchemaVersion) {
      return absl::FailedPreconditionError(StrCat(path.string(), ": store schema version ", version,
                                                  " (this build reads ", storage::kMinReadOnlySchemaVersion, " to ",
                                                  storage::kSchemaVersion, "; open it once with mocapd to migrate)"));
    }
    return std::unique_ptr<MotionStore>(new MotionStore(path, std::move(db)));
  } catch (const std::exception& error) {
    return FromException(error, StrCat("opening motion store ", path.string()));
  }
}

MotionStore::WriteBatch::WriteBatch(std::unique_ptr<SQLite::Transaction> transaction)
    : transaction_(std::move(transaction)) {}
MotionStore::WriteBatch::~WriteBatch() = default;

absl::Status MotionStore::WriteBatch::Commit() {
  try {
    transaction_->commit();
    return absl::OkStatus();
  } catch (const std::exception& error) {
    return FromException(error, "committing import");
  }
}

absl::StatusOr<std::unique_ptr<MotionStore::WriteBatch>> MotionStore::BeginWrite() {
  try {
    auto transaction = std::make_unique<SQLite::Transaction>(*db_, SQLite::TransactionBehavior::IMMEDIATE);
    return std::unique_ptr<WriteBatch>(new WriteBatch(std::move(transaction)));
  } catch (const std::exception& error) {
    return FromException(error, "starting a write");
  }
}

absl::Status CheckDatabaseName(std::string_view name) {
  if (name.empty() || name.size() > kMaxDatabaseNameBytes) {
    return absl::InvalidArgumentError(
        StrCat("database name must have 1 to ", kMaxDatabaseNameBytes, " bytes, not ", name.size()));
  }
  return absl::OkStatus();
}

absl::StatusOr<DatabaseSummary> MotionStore::FindDatabase(const std::string& name, TenantId tenant) {
  // Checked before the lookup, so an oversized name is neither looked up nor echoed back.
  MOCAP_RETURN_IF_ERROR(CheckDatabaseName(name));
  try {
    SQLite::Statement query(*db_, StrCat(kSummarySelect, " WHERE d.tenant_id = ? AND d.name = ?"));
    query.bind(1, tenant);
    query.bind(2, name);
    if (!query.executeStep()) return absl::NotFoundError(StrCat("no motion database named '", name, "'"));
    return SummaryFromRow(query);
  } catch (const std::exception& error) {
    return FromException(error, "finding database");
  }
}

absl::StatusOr<std::vector<DatabaseSummary>> MotionStore::ListDatabases(TenantId tenant) {
  try {
    SQLite::Statement query(*db_, StrCat(kSummarySelect, " WHERE d.tenant_id = ? ORDER BY d.name"));
    query.bind(1, tenant);
    std::vector<DatabaseSummary> out;
    while (query.executeStep()) {
      MOCAP_ASSIGN_OR_RETURN(DatabaseSummary summary, SummaryFromRow(query));
      out.push_back(std::move(summary));
    }
    return out;
  } catch (const std::exception& error) {
    return FromException(error, "listing databases");
  }
}

absl::StatusOr<DatabaseSummary> MotionStore::CreateDatabase(const std::string& name, const RigModel& rig,
                                                            double frame_rate, TenantId tenant) {
  return InsertDatabase(tenant, name, &rig, frame_rate);
}

absl::StatusOr<DatabaseSummary> MotionStore::CreateEmptyDatabase(const std::string& name, double frame_rate,
                                                                 TenantId tenant) {
  return InsertDatabase(tenant, name, nullptr, frame_rate);
}

absl::StatusOr<DatabaseSummary> MotionStore::InsertDatabase(TenantId tenant, const std::string& name,
                                                            const RigModel* rig, double frame_rate) {
  MOCAP_RETURN_IF_ERROR(CheckDatabaseName(name));
  if (!(frame_rate > 0 && frame_rate <= 1000)) {
    return absl::InvalidArgumentError(StrCat("database frame rate ", frame_rate, " is outside (0, 1000]"));
  }
  try {
    SQLite::Statement exists(*db_, "SELECT 1 FROM databases WHERE tenant_id = ? AND name = ?");
    exists.bind(1, tenant);
    exists.bind(2, name);
    if (exists.executeStep()) return absl::AlreadyExistsError(StrCat("motion database '", name, "' already exists"));
    SQLite::Statement insert(*db_,
                             "INSERT INTO databases (tenant_id, name, frame_rate, unit, rig) VALUES (?, ?, ?, ?, ?)");
    insert.bind(1, tenant);
    insert.bind(2, name);
    insert.bind(3, frame_rate);
    if (rig != nullptr) {
      insert.bind(4, std::string(UnitName(rig->unit)));
      insert.bind(5, storage::EncodeRig(*rig));
    }
    insert.exec();
  } catch (const std::exception& error) {
    return FromException(error, "creating database");
  }
  return FindDatabase(name, tenant);
}

absl::Status MotionStore::SetRig(const DatabaseRef& database, const RigModel& rig) {
  try {
    MOCAP_RETURN_IF_ERROR(CheckDatabaseExists(database));
    SQLite::Statement update(*db_, "UPDATE databases SET unit = ?, rig = ? WHERE id = ? AND rig IS NULL");
    update.bind(1, std::string(UnitName(rig.unit)));
    update.bind(2, storage::EncodeRig(rig));
    update.bind(3, database.id());
    if (update.exec() == 0)
      return absl::FailedPreconditionError(StrCat("motion database '", database.name(), "' has a rig already"));
    return absl::OkStatus();
  } catch (const std::exception& error) {
    return FromException(error, "setting the rig");
  }
}

absl::StatusOr<RigModel> MotionStore::LoadRig(const DatabaseRef& database) {
  try {
    SQLite::Statement query(*db_, "SELECT rig FROM databases WHERE id = ? AND tenant_id = ?");
    query.bind(1, database.id());
    query.bind(2, database.tenant());
    if (!query.executeStep()) return NoLongerExists(database);
    if (query.getColumn(0).isNull()) {
      return absl::FailedPreconditionError(
          StrCat("motion database '", database.name(), "' has no rig yet (nothing imported)"));
    }
    return storage::DecodeRig(query.getColumn(0).getString());
  } catch (const std::exception& error) {
    return FromException(error, "loading rig");
  }
}

absl::Status MotionStore::CheckDatabaseExists(const DatabaseRef& database) {
  try {
    SQLite::Statement query(*db_, "SELECT 1 FROM databases WHERE id = ? AND tenant_id = ? AND name = ?");
    query.bind(1, database.id());
    query.bind(2, database.tenant());
    query.bind(3, database.name());
    if (!query.executeStep()) return NoLongerExists(database);
    return absl::OkStatus();
  } catch (const std::exception& error) {
    return FromException(error, "checking database");
  }
}

absl::Status MotionStore::DeleteDatabase(const DatabaseRef& database) {
  try {
    SQLite::Statement remove(*db_, "DELETE FROM databases WHERE id = ? AND tenant_id = ?");
    remove.bind(1, database.id());
    remove.bind(2, database.tenant());
    if (remove.exec() == 0) return NoLongerExists(database);
    return absl::OkStatus();
  } catch (const std::exception& error) {
    return FromException(error, "deleting database");
  }
}

absl::StatusOr<std::optional<std::int64_t>> MotionStore::FindClipByHash(const DatabaseRef& database,
                                                                        const std::string& content_hash) {
  try {
    SQLite::Statement query(*db_, "SELECT id FROM clips WHERE database_id = ? AND content_hash = ?");
    query.bind(1, database.id());
    query.bind(2, content_hash);
    if (!query.executeStep()) return std::optional<std::int64_t>();
    return std::optional<std::int64_t>(query.getColumn(0).getInt64());
  } catch (const std::exception& error) {
    return FromException(error, "looking up clip");
  }
}

absl::StatusOr<std::int64_t> MotionStore::InsertClip(const DatabaseRef& database, const std::string& source_name,
                                                     const std::string& content_hash, const ClipLabels& labels,
                                                     const PreparedClip& clip, const RigModel& rig) {
  const int joints = clip.skeleton.num_joints();
  std::vector<float> offsets(static_cast<size_t>(joints) * 3);
  for (int j = 0; j < joints; ++j) {
    for (int axis = 0; axis < 3; ++axis) offsets[3 * j + axis] = clip.skeleton.joint(j).offset[axis];
  }
  const std::vector<float> poses = EncodePoses(clip.motion, rig);
  const size_t animated = clip.animated_joints.size();
  std::vector<float> translations(static_cast<size_t>(clip.num_frames()) * animated * 3);
  std::string animated_list;
  for (size_t k = 0; k < animated; ++k) {
    animated_list += (k ? "," : "") + std::to_string(clip.animated_joints[k]);
    for (int f = 0; f < clip.num_frames(); ++f) {
      const Eigen::Vector3f t = clip.motion.translation(f, clip.animated_joints[k]);
      for (int axis = 0; axis < 3; ++axis) translations[(static_cast<size_t>(f) * animated + k) * 3 + axis] = t[axis];
    }
  }
  try {
    MOCAP_RETURN_IF_ERROR(CheckDatabaseExists(database));
    SQLite::Statement insert(*db_, R"sql(
      INSERT INTO clips (database_id, source_name, content_hash, source_frame_rate, source_frames, num_frames,
                         offsets, poses, animated_joints, translations, features)
      VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?))sql");
    insert.bind(1, database.id());
    insert.bind(2, source_name);
    insert.bind(3, content_hash);
    insert.bind(4, clip.source_frame_rate);
    insert.bind(5, clip.source_frames);
    insert.bind(6, clip.num_frames());
    BindFloats(insert, 7, offsets);
    BindFloats(insert, 8, poses);
    insert.bind(9, animated_list);
    if (animated > 0) {
      BindFloats(insert, 10, translations);
    } else {
      insert.bind(10);
    }
    BindFloats(insert, 11, clip.features);
    insert.exec();
    const std::int64_t clip_id = db_->getLastInsertRowid();
    SQLite::Statement label(*db_, "INSERT OR REPLACE INTO clip_labels (clip_id, key, value) VALUES (?, ?, ?)");
    for (const auto& [key, value] : labels) {
      label.bind(1, clip_id);
      label.bind(2, key);
      label.bind(3, value);
      label.exec();
      label.reset();
    }
    return clip_id;
  } catch (const std::exception& error) {
    return FromException(error, StrCat("storing clip ", source_name));
  }
}

absl::StatusOr<std::string> MotionStore::ContentStamp(const DatabaseRef& database) {
  const std::int64_t database_id = database.id();
  try {
    // data_version first: a commit landing between it and the listing makes the next call list
    // again, never keeps a stale stamp.
    const std::int64_t data_version = db_->execAndGet("PRAGMA data_version").getInt64();
    const std::int64_t total_changes = db_->getTotalChanges();
    if (data_version != stamp_cache_.data_version || total_changes != stamp_cache_.total_changes) {
      stamp_cache_ = {.data_version = data_version, .total_changes = total_changes, .stamps = {}};
    }
    if (auto it = stamp_cache_.stamps.find(database_id); it != stamp_cache_.stamps.end()) return it->second;
    // The database's identity (tenant, name, creation) is part of the stamp: whatever is built
    // and named from one database can never be taken for another's, even if an id repeated.
    SQLite::Statement identity(*db_,
                               "SELECT tenant_id, name, created_at FROM databases WHERE id = ? AND tenant_id = ?");
    identity.bind(1, database_id);
    identity.bind(2, database.tenant());
    if (!identity.executeStep()) return NoLongerExists(database);
    const std::string owner = StrCat(identity.getColumn(0).getInt64(), "/", identity.getColumn(1).getString(), "/",
                                     identity.getColumn(2).getString());
    SQLite::Statement query(*db_, "SELECT id, content_hash FROM clips WHERE database_id = ? ORDER BY id");
    query.bind(1, database_id);
    // Ids alone could repeat after a delete and an import; the content hashes cannot.
    std::size_t hash = std::hash<std::int64_t>()(database_id) ^ std::hash<std::string>()(owner);
    std::int64_t count = 0;
    while (query.executeStep()) {
      hash = hash * 1000003u ^ std::hash<std::int64_t>()(query.getColumn(0).getInt64());
      hash = hash * 1000003u ^ std::hash<std::string>()(query.getColumn(1).getString());
      ++count;
    }
    std::string stamp = StrCat(count, "-", hash);
    stamp_cache_.stamps[database_id] = stamp;
    return stamp;
  } catch (const std::exception& error) {
    return FromException(error, "reading the database's content stamp");
  }
}

absl::StatusOr<std::vector<ClipSummary>> MotionStore::ListClips(const DatabaseRef& database) {
  const std::int64_t database_id = database.id();
  try {
    std::vector<ClipSummary> clips;
    SQLite::Statement query(*db_, R"sql(
      SELECT id, source_name, content_hash, num_frames, source_frame_rate, source_frames
      FROM clips WHERE database_id = ? ORDER BY id)sql");
    query.bind(1, database_id);
    while (query.executeStep()) clips.push_back(ClipFromRow(query));
    SQLite::Statement labels(*db_, R"sql(
      SELECT l.clip_id, l.key, l.value FROM clip_labels l JOIN clips c ON c.id = l.clip_id
      WHERE c.database_id = ? ORDER BY l.clip_id, l.key)sql");
    labels.bind(1, database_id);
    size_t cursor = 0;
    while (labels.executeStep()) {
      const std::int64_t clip_id = labels.getColumn(0).getInt64();
      while (cursor < clips.size() && clips[cursor].id < clip_id) ++cursor;
      if (cursor < clips.size() && clips[cursor].id == clip_id) {
        clips[cursor].labels.emplace_back(labels.getColumn(1).getString(), labels.getColumn(2).getString());
      }
    }
    return clips;
  } catch (const std::exception& error) {
    return FromException(error, "listing clips");
  }
}

absl::StatusOr<ClipSummary> MotionStore::FindClip(const DatabaseRef& database, std::int64_t clip_id) {
  try {
    SQLite::Statement query(*db_, R"sql(
      SELECT id, source_name, content_hash, num_frames, source_frame_rate, source_frames
      FROM clips WHERE database_id = ? AND id = ?)sql");
    query.bind(1, database.id());
    query.bind(2, clip_id);
    if (!query.executeStep()) return absl::NotFoundError(StrCat("no clip ", clip_id, " in this database"));
    return ClipFromRow(query);
  } catch (const std::exception& error) {
    return FromException(error, "finding clip");
  }
}

absl::Status MotionStore::DeleteClip(const DatabaseRef& database, std::int64_t clip_id) {
  try {
    SQLite::Statement remove(*db_, "DELETE FROM clips WHERE database_id = ? AND id = ?");
    remove.bind(1, database.id());
    remove.bind(2, clip_id);
    if (remove.exec() == 0) return absl::NotFoundError(StrCat("no clip ", clip_id, " in this database"));
    return absl::OkStatus();
  } catch (const std::exception& error) {
    return FromException(error, "deleting clip");
  }
}

absl::StatusOr<StoredClip> MotionStore::LoadClip(const DatabaseRef& database, std::int64_t clip_id,
                                                 const RigModel& rig) {
  try {
    SQLite::Statement query(*db_, R"sql(
      SELECT c.source_name, c.content_hash, c.num_frames, c.source_frame_rate, c.source_frames,
             c.offsets, c.poses, c.translations, c.features, d.frame_rate, c.animated_joints
      FROM clips c JOIN databases d ON d.id = c.database_id WHERE c.id = ? AND c.database_id = ?)sql");
    query.bind(1, clip_id);
    query.bind(2, database.id());
    if (!query.executeStep()) return absl::NotFoundError(StrCat("no clip ", clip_id, " in this database"));
    StoredClip out;
    out.summary.id = clip_id;
    out.summary.source_name = query.getColumn(0).getString();
    out.summary.content_hash = query.getColumn(1).getString();
    out.summary.num_frames = query.getColumn(2).getInt();
    out.summary.source_frame_rate = query.getColumn(3).getDouble();
    out.summary.source_frames = query.getColumn(4).getInt();
    const int frames = out.summary.num_frames;
    const int joints = rig.skeleton.num_joints();
    std::vector<float> offsets, poses, translations;
    MOCAP_RETURN_IF_ERROR(ReadFloats(query.getColumn(5), static_cast<size_t>(joints) * 3, offsets, "offsets"));
    MOCAP_RETURN_IF_ERROR(
        ReadFloats(query.getColumn(6), static_cast<size_t>(frames) * EncodedPoseFloats(joints), poses, "poses"));
    std::vector<int> animated_joints;
    {
      const std::string list = query.getColumn(10).getString();
      size_t start = 0;
      while (start < list.size()) {
        size_t end = list.find(',', start);
        if (end == std::string::npos) end = list.size();
        const int joint = std::atoi(list.substr(start, end - start).c_str());
        if (joint <= 0 || joint >= joints)
          return absl::DataLossError(StrCat("clip ", clip_id, " has a bad animated joint list"));
        animated_joints.push_back(joint);
        start = end + 1;
      }
    }
    const size_t animated = animated_joints.size();
    if (animated > 0) {
      MOCAP_RETURN_IF_ERROR(
          ReadFloats(query.getColumn(7), static_cast<size_t>(frames) * animated * 3, translations, "translations"));
    }
    MOCAP_RETURN_IF_ERROR(ReadFloats(query.getColumn(8), static_cast<size_t>(frames), out.features, "features"));
    const double frame_time = 1.0 / query.getColumn(9).getDouble();
    std::vector<Joint> skeleton_joints = rig.skeleton.joints();
    // Offsets are stored in metres per clip; End Sites are the rig's, in the rig's file unit.
    const float end_site_metres = static_cast<float>(MetresPerUnit(rig.unit));
    for (int j = 0; j < joints; ++j) {
      skeleton_joints[j].offset = Eigen::Vector3f(offsets[3 * j], offsets[3 * j + 1], offsets[3 * j + 2]);
      if (skeleton_joints[j].end_site) *skeleton_joints[j].end_site *= end_site_metres;
    }
    out.skeleton = Skeleton(std::move(skeleton_joints));
    out.motion = DecodePoses(poses, out.skeleton, rig, frame_time);
    for (int f = 0; f < frames; ++f) {
      for (size_t k = 0; k < animated; ++k) {
        const float* t = translations.data() + (static_cast<size_t>(f) * animated + k) * 3;
        out.motion.SetTranslation(f, animated_joints[k], Eigen::Vector3f(t[0], t[1], t[2]));
      }
    }
    SQLite::Statement labels(*db_, "SELECT key, value FROM clip_labels WHERE clip_id = ? ORDER BY key");
    labels.bind(1, clip_id);
    while (labels.executeStep())
      out.summary.labels.emplace_back(labels.getColumn(0).getString(), labels.getColumn(1).getString());
    return out;
  } catch (const std::exception& error) {
    return FromException(error, StrCat("loading clip ", clip_id));
  }
}

}  // namespace mocap

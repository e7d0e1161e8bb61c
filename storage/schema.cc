#include "storage/schema.h"

#include <SQLiteCpp/Statement.h>
#include <SQLiteCpp/Transaction.h>

#include "motion/core/str_cat.h"

namespace mocap::storage {
namespace {

// Migration N takes the schema from version N-1 to N. Append only; never edit a released one.
constexpr const char* kMigrations[] = {
    // 1: databases (one rig each), clips with float32 blobs, labels.
    R"sql(
CREATE TABLE databases (
  id          INTEGER PRIMARY KEY,
  name        TEXT NOT NULL UNIQUE,
  frame_rate  REAL NOT NULL CHECK (frame_rate > 0),
  unit        TEXT NOT NULL,
  rig         TEXT NOT NULL,              -- JSON: skeleton, topology, reference rotations
  created_at  TEXT NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%SZ', 'now'))
);
CREATE TABLE clips (
  id                INTEGER PRIMARY KEY,
  database_id       INTEGER NOT NULL REFERENCES databases(id) ON DELETE CASCADE,
  source_name       TEXT NOT NULL,        -- imported file name
  content_hash      TEXT NOT NULL,        -- XXH3-128 of the file bytes, hex
  source_frame_rate REAL NOT NULL,
  source_frames     INTEGER NOT NULL,
  num_frames        INTEGER NOT NULL CHECK (num_frames > 0),
  offsets           BLOB NOT NULL,        -- float32[joints][3], metres: this performer's bones
  poses             BLOB NOT NULL,        -- float32[frames][3 + 3 * joints]: root position, rotation vectors
  animated_joints   TEXT NOT NULL DEFAULT '',  -- comma-separated non-root joints whose translation moves
  translations      BLOB,                 -- float32[frames][animated joints][3], metres
  features          BLOB NOT NULL,        -- float32[frames][36]: FrameFeatures (METHOD.md A1)
  imported_at       TEXT NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%SZ', 'now')),
  UNIQUE (database_id, content_hash)
);
CREATE INDEX clips_by_database ON clips(database_id);
CREATE TABLE clip_labels (
  clip_id INTEGER NOT NULL REFERENCES clips(id) ON DELETE CASCADE,
  key     TEXT NOT NULL,
  value   TEXT NOT NULL,
  PRIMARY KEY (clip_id, key)
);
CREATE INDEX clip_labels_by_value ON clip_labels(key, value);
)sql",
    // 2: tenants and their API keys; every database belongs to a tenant (names unique per
    // tenant); a database may exist before its first import (rig and unit NULL until then).
    // Version 1 databases go to tenant 1, 'default'. SQLite cannot drop the old UNIQUE (name),
    // so the table is rebuilt (https://sqlite.org/lang_altertable.html, "other kinds of table
    // schema changes"); MigrateSchema turns foreign keys off around it.
    R"sql(
CREATE TABLE tenants (
  id          INTEGER PRIMARY KEY,
  name        TEXT NOT NULL UNIQUE,
  created_at  TEXT NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%SZ', 'now'))
);
INSERT INTO tenants (id, name) VALUES (1, 'default');
CREATE TABLE api_keys (
  id          INTEGER PRIMARY KEY,
  tenant_id   INTEGER NOT NULL REFERENCES tenants(id) ON DELETE CASCADE,
  key_id      TEXT NOT NULL UNIQUE,       -- public part of the key ("mk_" + 8 hex), safe to show
  key_sha256  TEXT NOT NULL UNIQUE,       -- SHA-256 of the whole key, hex; the key is never stored
  created_at  TEXT NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%SZ', 'now')),
  revoked_at  TEXT
);
CREATE INDEX api_keys_by_tenant ON api_keys(tenant_id);
CREATE TABLE databases_v2 (
  id          INTEGER PRIMARY KEY,
  tenant_id   INTEGER NOT NULL REFERENCES tenants(id),
  name        TEXT NOT NULL,
  frame_rate  REAL NOT NULL CHECK (frame_rate > 0),
  unit        TEXT,                       -- NULL until the first import fixes the rig
  rig         TEXT,                       -- JSON: skeleton, topology, reference rotations
  created_at  TEXT NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%SZ', 'now')),
  UNIQUE (tenant_id, name)
);
INSERT INTO databases_v2 (id, tenant_id, name, frame_rate, unit, rig, created_at)
  SELECT id, 1, name, frame_rate, unit, rig, created_at FROM databases;
DROP TABLE databases;
ALTER TABLE databases_v2 RENAME TO databases;
)sql",
    // 3: database and clip ids are never reused (AUTOINCREMENT): an id a caller still holds
    // (an open import, a cached index, a client's clip id) can never name another tenant's
    // database or clip after a delete. Both tables are rebuilt (SQLite cannot add the keyword);
    // copying the rows with their ids sets sqlite_sequence to the highest id in use.
    R"sql(
CREATE TABLE databases_v3 (
  id          INTEGER PRIMARY KEY AUTOINCREMENT,
  tenant_id   INTEGER NOT NULL REFERENCES tenants(id),
  name        TEXT NOT NULL,
  frame_rate  REAL NOT NULL CHECK (frame_rate > 0),
  unit        TEXT,
  rig         TEXT,
  created_at  TEXT NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%SZ', 'now')),
  UNIQUE (tenant_id, name)
);
INSERT INTO databases_v3 (id, tenant_id, name, frame_rate, unit, rig, created_at)
  SELECT id, tenant_id, name, frame_rate, unit, rig, created_at FROM databases;
DROP TABLE databases;
ALTER TABLE databases_v3 RENAME TO databases;
CREATE TABLE clips_v3 (
  id                INTEGER PRIMARY KEY AUTOINCREMENT,
  database_id       INTEGER NOT NULL REFERENCES databases(id) ON DELETE CASCADE,
  source_name       TEXT NOT NULL,
  content_hash      TEXT NOT NULL,
  source_frame_rate REAL NOT NULL,
  source_frames     INTEGER NOT NULL,
  num_frames        INTEGER NOT NULL CHECK (num_frames > 0),
  offsets           BLOB NOT NULL,
  poses             BLOB NOT NULL,
  animated_joints   TEXT NOT NULL DEFAULT '',
  translations      BLOB,
  features          BLOB NOT NULL,
  imported_at       TEXT NOT NULL DEFAULT (strftime('%Y-%m-%dT%H:%M:%SZ', 'now')),
  UNIQUE (database_id, content_hash)
);
INSERT INTO clips_v3 SELECT id, database_id, source_name, content_hash, source_frame_rate, source_frames, num_frames,
                            offsets, poses, animated_joints, translations, features, imported_at FROM clips;
DROP TABLE clips;
ALTER TABLE clips_v3 RENAME TO clips;
CREATE INDEX clips_by_database ON clips(database_id);
)sql",
    // 4: a database's clip count and frame total (read at every session's start and listing) from
    // an index alone. A clip's row is a 4 KB page or more (its motion blobs), so summing num_frames
    // through the table read every clip's page: 9.5 MB for a 2,316-clip database, 5-10 ms of each
    // session's setup (issue #24). The content stamp's (id, content_hash) then come from the
    // UNIQUE index, also without the table.
    R"sql(
DROP INDEX clips_by_database;
CREATE INDEX clips_frames_by_database ON clips(database_id, num_frames);
)sql",
};
static_assert(sizeof(kMigrations) / sizeof(kMigrations[0]) == kSchemaVersion);

}  // namespace

int SchemaVersion(SQLite::Database& db) { return db.execAndGet("PRAGMA user_version").getInt(); }

absl::Status MigrateSchema(SQLite::Database& db, int target_version) {
  int version = SchemaVersion(db);
  if (version > kSchemaVersion) {
    return absl::FailedPreconditionError(StrCat(
        "store schema version ", version, " is newer than this build supports (", kSchemaVersion, "); upgrade mocapd"));
  }
  if (version >= target_version) return absl::OkStatus();
  // Table rebuilds (migration 2) need foreign keys off; the pragma is a no-op inside a
  // transaction, so it is set around them and the keys are checked before each commit.
  const bool foreign_keys = db.execAndGet("PRAGMA foreign_keys").getInt() != 0;
  db.exec("PRAGMA foreign_keys = OFF");
  absl::Status status = absl::OkStatus();
  try {
    while (version < target_version) {
      SQLite::Transaction transaction(db);
      db.exec(kMigrations[version]);
      ++version;
      SQLite::Statement check(db, "PRAGMA foreign_key_check");
      if (check.executeStep()) {
        status = absl::DataLossError(StrCat("store schema migration to version ", version, " found rows of table '",
                                            check.getColumn(0).getString(), "' with a broken reference"));
        break;  // rolled back
      }
      db.exec(StrCat("PRAGMA user_version = ", version));
      transaction.commit();
    }
  } catch (...) {
    if (foreign_keys) db.exec("PRAGMA foreign_keys = ON");
    throw;
  }
  if (foreign_keys) db.exec("PRAGMA foreign_keys = ON");
  return status;
}

}  // namespace mocap::storage

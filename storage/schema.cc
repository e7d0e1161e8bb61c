#include "storage/schema.h"

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
};
static_assert(sizeof(kMigrations) / sizeof(kMigrations[0]) == kSchemaVersion);

}  // namespace

int SchemaVersion(SQLite::Database& db) { return db.execAndGet("PRAGMA user_version").getInt(); }

absl::Status MigrateSchema(SQLite::Database& db) {
  int version = SchemaVersion(db);
  if (version > kSchemaVersion) {
    return absl::FailedPreconditionError(StrCat("store schema version ", version,
                                                " is newer than this build supports (", kSchemaVersion,
                                                "); upgrade mocapd"));
  }
  while (version < kSchemaVersion) {
    SQLite::Transaction transaction(db);
    db.exec(kMigrations[version]);
    ++version;
    db.exec(StrCat("PRAGMA user_version = ", version));
    transaction.commit();
  }
  return absl::OkStatus();
}

}  // namespace mocap::storage

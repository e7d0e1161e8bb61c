// Schema of the motion store and its migrations (PRAGMA user_version holds the version).
#pragma once

#include <SQLiteCpp/Database.h>

#include "absl/status/status.h"

namespace mocap::storage {

inline constexpr int kSchemaVersion = 4;
// Read-only opens (which cannot migrate) accept these older versions too: their tables read the same.
inline constexpr int kMinReadOnlySchemaVersion = 2;

// Brings the schema up to `target_version` (tests stop early to write older stores), one
// migration per transaction. FailedPrecondition when the file was written by a newer build (its
// version is higher than ours).
absl::Status MigrateSchema(SQLite::Database& db, int target_version = kSchemaVersion);

int SchemaVersion(SQLite::Database& db);

}  // namespace mocap::storage

#include "storage/sqlite_status.h"

#include <SQLiteCpp/Exception.h>
#include <sqlite3.h>

#include "motion/core/str_cat.h"

namespace mocap::storage {

absl::Status FromException(const std::exception& error, std::string_view what) {
  const auto* sqlite_error = dynamic_cast<const SQLite::Exception*>(&error);
  const std::string message = StrCat(what, ": ", error.what());
  if (sqlite_error != nullptr) {
    const int code = sqlite_error->getErrorCode();
    if (code == SQLITE_BUSY || code == SQLITE_LOCKED) return absl::UnavailableError(message);
    if (code == SQLITE_CORRUPT || code == SQLITE_NOTADB) return absl::DataLossError(message);
    if (code == SQLITE_READONLY || code == SQLITE_CANTOPEN || code == SQLITE_PERM) {
      return absl::PermissionDeniedError(message);
    }
    if (code == SQLITE_FULL) return absl::ResourceExhaustedError(message);
  }
  return absl::InternalError(message);
}

}  // namespace mocap::storage

// SQLiteCpp throws SQLite::Exception; storage/ turns every exception into a status here.
#pragma once

#include <exception>
#include <string_view>

#include "absl/status/status.h"

namespace mocap::storage {

// Busy/locked -> Unavailable, corrupt -> DataLoss, read-only/permissions -> PermissionDenied,
// disk full -> ResourceExhausted, anything else -> Internal; the message starts with `what`.
absl::Status FromException(const std::exception& error, std::string_view what);

}  // namespace mocap::storage

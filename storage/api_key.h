// API keys: random bearer secrets shown once; only their SHA-256 is stored.
//
// A key reads "mk_<8 hex>_<48 hex>": the first 11 characters ("mk_" and 8 hex) are its public
// id, shown in listings and used to revoke it; the whole key carries 224 random bits.
#pragma once

#include <string>
#include <string_view>

#include "absl/status/statusor.h"

namespace mocap::storage {

struct GeneratedApiKey {
  std::string key;     // give to the client; never stored
  std::string key_id;  // public prefix of the key
  std::string sha256;  // lowercase hex SHA-256 of the whole key, as stored
};

// Internal when the system's random source fails.
absl::StatusOr<GeneratedApiKey> GenerateApiKey();

// Lowercase hex SHA-256 of `key`.
std::string HashApiKey(std::string_view key);

}  // namespace mocap::storage

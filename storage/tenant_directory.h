// TenantDirectory: the tenants of a store and their API keys (schema version 2).
//
// Works on a MotionStore's connection: same thread rule as the store (one thread at a time).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "storage/motion_store.h"

namespace mocap {

struct Tenant {
  TenantId id = 0;
  std::string name;
  std::string created_at;  // UTC, ISO 8601
  int active_keys = 0;
  int databases = 0;
};

struct ApiKeyInfo {
  std::string key_id;  // the key's public prefix
  std::string created_at;
  std::optional<std::string> revoked_at;
};

// A key as just made: `key` is shown this once and never stored.
struct NewApiKey {
  std::string tenant;
  std::string key_id;
  std::string key;
};

class TenantDirectory {
 public:
  explicit TenantDirectory(MotionStore& store);

  // InvalidArgument for a name that is empty, over 64 characters or not [A-Za-z0-9._-];
  // AlreadyExists when taken.
  absl::StatusOr<Tenant> CreateTenant(const std::string& name);
  // NotFound when there is no such tenant.
  absl::StatusOr<Tenant> FindTenant(const std::string& name);
  absl::StatusOr<std::vector<Tenant>> ListTenants();
  absl::StatusOr<std::vector<ApiKeyInfo>> ListKeys(TenantId tenant);
  absl::StatusOr<NewApiKey> AddKey(TenantId tenant);
  // NotFound when the tenant has no active key with that id (or, given the whole key, its id).
  absl::Status RevokeKey(TenantId tenant, const std::string& key_id_or_key);
  // The tenant an active key belongs to; Unauthenticated otherwise (unknown or revoked).
  absl::StatusOr<Tenant> Authenticate(std::string_view key);

 private:
  absl::StatusOr<Tenant> FindTenantWhere(const char* condition, const std::string& value);
  MotionStore& store_;
};

// The id of the tenant called `name`; kDefaultTenantId for an empty name. NotFound otherwise.
absl::StatusOr<TenantId> ResolveTenant(MotionStore& store, const std::string& name);

}  // namespace mocap

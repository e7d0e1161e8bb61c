#include "storage/tenant_directory.h"

#include <SQLiteCpp/Database.h>
#include <SQLiteCpp/Statement.h>

#include "motion/core/status_macros.h"
#include "motion/core/str_cat.h"
#include "storage/api_key.h"
#include "storage/sqlite_status.h"

namespace mocap {
namespace {

using storage::FromException;

constexpr const char* kTenantSelect = R"sql(
  SELECT t.id, t.name, t.created_at,
         (SELECT COUNT(*) FROM api_keys k WHERE k.tenant_id = t.id AND k.revoked_at IS NULL),
         (SELECT COUNT(*) FROM databases d WHERE d.tenant_id = t.id)
  FROM tenants t)sql";

Tenant TenantFromRow(SQLite::Statement& query) {
  return Tenant{.id = query.getColumn(0).getInt64(),
                .name = query.getColumn(1).getString(),
                .created_at = query.getColumn(2).getString(),
                .active_keys = query.getColumn(3).getInt(),
                .databases = query.getColumn(4).getInt()};
}

bool ValidTenantName(const std::string& name) {
  if (name.empty() || name.size() > 64) return false;
  for (char c : name) {
    const bool ok =
        (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' || c == '_' || c == '-';
    if (!ok) return false;
  }
  return true;
}

}  // namespace

TenantDirectory::TenantDirectory(MotionStore& store) : store_(store) {}

absl::StatusOr<Tenant> TenantDirectory::FindTenantWhere(const char* condition, const std::string& value) {
  try {
    SQLite::Statement query(*store_.db_, StrCat(kTenantSelect, " WHERE ", condition));
    query.bind(1, value);
    if (!query.executeStep()) return absl::NotFoundError(StrCat("no tenant named '", value, "'"));
    return TenantFromRow(query);
  } catch (const std::exception& error) {
    return FromException(error, "finding tenant");
  }
}

absl::StatusOr<Tenant> TenantDirectory::CreateTenant(const std::string& name) {
  if (!ValidTenantName(name)) {
    return absl::InvalidArgumentError(
        StrCat("tenant name '", name, "' must have 1 to 64 characters among letters, digits, '.', '_' and '-'"));
  }
  try {
    SQLite::Statement insert(*store_.db_, "INSERT INTO tenants (name) VALUES (?) ON CONFLICT (name) DO NOTHING");
    insert.bind(1, name);
    if (insert.exec() == 0) return absl::AlreadyExistsError(StrCat("tenant '", name, "' already exists"));
  } catch (const std::exception& error) {
    return FromException(error, "creating tenant");
  }
  return FindTenant(name);
}

absl::StatusOr<Tenant> TenantDirectory::FindTenant(const std::string& name) {
  return FindTenantWhere("t.name = ?", name);
}

absl::StatusOr<std::vector<Tenant>> TenantDirectory::ListTenants() {
  try {
    SQLite::Statement query(*store_.db_, StrCat(kTenantSelect, " ORDER BY t.name"));
    std::vector<Tenant> out;
    while (query.executeStep()) out.push_back(TenantFromRow(query));
    return out;
  } catch (const std::exception& error) {
    return FromException(error, "listing tenants");
  }
}

absl::StatusOr<std::vector<ApiKeyInfo>> TenantDirectory::ListKeys(TenantId tenant) {
  try {
    SQLite::Statement query(*store_.db_,
                            "SELECT key_id, created_at, revoked_at FROM api_keys WHERE tenant_id = ? ORDER BY id");
    query.bind(1, tenant);
    std::vector<ApiKeyInfo> out;
    while (query.executeStep()) {
      ApiKeyInfo key{.key_id = query.getColumn(0).getString(), .created_at = query.getColumn(1).getString()};
      if (!query.getColumn(2).isNull()) key.revoked_at = query.getColumn(2).getString();
      out.push_back(std::move(key));
    }
    return out;
  } catch (const std::exception& error) {
    return FromException(error, "listing keys");
  }
}

absl::StatusOr<NewApiKey> TenantDirectory::AddKey(TenantId tenant) {
  // A clash of the 32-bit public id is rare; a few fresh tries settle it.
  for (int attempt = 0; attempt < 5; ++attempt) {
    MOCAP_ASSIGN_OR_RETURN(storage::GeneratedApiKey key, storage::GenerateApiKey());
    try {
      SQLite::Statement insert(*store_.db_, R"sql(
        INSERT INTO api_keys (tenant_id, key_id, key_sha256) VALUES (?, ?, ?) ON CONFLICT DO NOTHING)sql");
      insert.bind(1, tenant);
      insert.bind(2, key.key_id);
      insert.bind(3, key.sha256);
      if (insert.exec() == 0) continue;
      SQLite::Statement name(*store_.db_, "SELECT name FROM tenants WHERE id = ?");
      name.bind(1, tenant);
      return NewApiKey{.tenant = name.executeStep() ? name.getColumn(0).getString() : std::string(),
                       .key_id = key.key_id,
                       .key = key.key};
    } catch (const std::exception& error) {
      return FromException(error, "adding key");
    }
  }
  return absl::InternalError("could not make a key with a fresh id");
}

absl::Status TenantDirectory::RevokeKey(TenantId tenant, const std::string& key_id_or_key) {
  // The whole key names its id too.
  const std::string key_id = key_id_or_key.substr(0, 11);
  try {
    SQLite::Statement update(*store_.db_, R"sql(
      UPDATE api_keys SET revoked_at = strftime('%Y-%m-%dT%H:%M:%SZ', 'now')
      WHERE tenant_id = ? AND key_id = ? AND revoked_at IS NULL)sql");
    update.bind(1, tenant);
    update.bind(2, key_id);
    if (update.exec() == 0) return absl::NotFoundError(StrCat("the tenant has no active key '", key_id, "'"));
    return absl::OkStatus();
  } catch (const std::exception& error) {
    return FromException(error, "revoking key");
  }
}

absl::StatusOr<Tenant> TenantDirectory::Authenticate(std::string_view key) {
  if (key.empty()) return absl::UnauthenticatedError("no API key");
  try {
    SQLite::Statement query(*store_.db_, StrCat(kTenantSelect, R"sql(
      WHERE t.id = (SELECT tenant_id FROM api_keys WHERE key_sha256 = ? AND revoked_at IS NULL))sql"));
    query.bind(1, storage::HashApiKey(key));
    if (!query.executeStep()) return absl::UnauthenticatedError("unknown or revoked API key");
    return TenantFromRow(query);
  } catch (const std::exception& error) {
    return FromException(error, "checking key");
  }
}

absl::StatusOr<TenantId> ResolveTenant(MotionStore& store, const std::string& name) {
  if (name.empty()) return kDefaultTenantId;
  MOCAP_ASSIGN_OR_RETURN(Tenant tenant, TenantDirectory(store).FindTenant(name));
  return tenant.id;
}

}  // namespace mocap

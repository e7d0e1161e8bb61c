// `mocapd tenant create|list|add-key|revoke-key`: tenants and API keys of a store.
#include <iostream>
#include <memory>

#include <nlohmann/json.hpp>

#include "mocapd/commands.h"
#include "storage/tenant_directory.h"

namespace mocap {
namespace {

struct TenantOptions {
  std::string store = "var/mocap.db";
  std::string name;
  std::string key_id;
  bool json = false;
};

// Runs `action` on the store's tenant directory, mapping errors to exit codes.
int WithDirectory(const TenantOptions& options, bool create_store,
                  const std::function<int(MotionStore&, TenantDirectory&)>& action) {
  auto store = MotionStore::Open(options.store, StoreOpenOptions{.create_if_missing = create_store});
  if (!store.ok()) return ReportError(store.status());
  TenantDirectory directory(**store);
  return action(**store, directory);
}

nlohmann::json TenantJson(const Tenant& tenant, const std::vector<ApiKeyInfo>& keys) {
  nlohmann::json key_list = nlohmann::json::array();
  for (const ApiKeyInfo& key : keys) {
    key_list.push_back({{"key_id", key.key_id},
                        {"created_at", key.created_at},
                        {"revoked_at", key.revoked_at ? nlohmann::json(*key.revoked_at) : nlohmann::json(nullptr)}});
  }
  return {{"name", tenant.name},
          {"created_at", tenant.created_at},
          {"databases", tenant.databases},
          {"active_keys", tenant.active_keys},
          {"keys", key_list}};
}

}  // namespace

void RegisterTenantCommands(CLI::App& app, CommandRegistry& registry) {
  auto options = std::make_shared<TenantOptions>();
  CLI::App* tenant = app.add_subcommand("tenant", "Tenants and their API keys (keys are stored hashed)");
  tenant->require_subcommand(1);
  auto add_common = [&](CLI::App* command) {
    command->add_option("--store", options->store, "Motion store file")->capture_default_str();
    command->add_flag("--json", options->json, "Print JSON");
  };

  CLI::App* create = tenant->add_subcommand("create", "Create a tenant (creates the store when missing)");
  create->add_option("name", options->name, "Tenant name: letters, digits, '.', '_', '-'")->required();
  add_common(create);
  registry.Add(create, [options] {
    return WithDirectory(*options, true, [&](MotionStore&, TenantDirectory& directory) {
      auto created = directory.CreateTenant(options->name);
      if (!created.ok()) return ReportError(created.status());
      if (options->json) {
        std::cout << TenantJson(*created, {}).dump(2) << "\n";
      } else {
        std::cout << "tenant '" << created->name << "' created; give it a key with: mocapd tenant add-key "
                  << created->name << "\n";
      }
      return 0;
    });
  });

  CLI::App* list = tenant->add_subcommand("list", "List tenants with their key ids and database counts");
  add_common(list);
  registry.Add(list, [options] {
    return WithDirectory(*options, false, [&](MotionStore&, TenantDirectory& directory) {
      auto tenants = directory.ListTenants();
      if (!tenants.ok()) return ReportError(tenants.status());
      nlohmann::json out = nlohmann::json::array();
      for (const Tenant& t : *tenants) {
        auto keys = directory.ListKeys(t.id);
        if (!keys.ok()) return ReportError(keys.status());
        if (options->json) {
          out.push_back(TenantJson(t, *keys));
          continue;
        }
        std::cout << t.name << ": " << t.databases << " database(s), " << t.active_keys << " active key(s)";
        for (const ApiKeyInfo& key : *keys) {
          if (!key.revoked_at) std::cout << " " << key.key_id;
        }
        std::cout << "\n";
      }
      if (options->json) std::cout << out.dump(2) << "\n";
      return 0;
    });
  });

  CLI::App* add_key = tenant->add_subcommand("add-key", "Make an API key for a tenant; it is printed once, only here");
  add_key->add_option("name", options->name, "Tenant name")->required();
  add_common(add_key);
  registry.Add(add_key, [options] {
    return WithDirectory(*options, false, [&](MotionStore&, TenantDirectory& directory) {
      auto tenant = directory.FindTenant(options->name);
      if (!tenant.ok()) return ReportError(tenant.status());
      auto key = directory.AddKey(tenant->id);
      if (!key.ok()) return ReportError(key.status());
      if (options->json) {
        std::cout << nlohmann::json{{"tenant", key->tenant}, {"key_id", key->key_id}, {"key", key->key}}.dump(2)
                  << "\n";
      } else {
        std::cerr << "API key " << key->key_id << " for tenant '" << key->tenant
                  << "' (shown once; only its hash is stored):\n";
        std::cout << key->key << "\n";
      }
      return 0;
    });
  });

  CLI::App* revoke =
      tenant->add_subcommand("revoke-key", "Revoke a tenant's API key by its id (the mk_xxxxxxxx prefix)");
  revoke->add_option("name", options->name, "Tenant name")->required();
  revoke->add_option("key_id", options->key_id, "Key id, as `tenant list` shows it")->required();
  add_common(revoke);
  registry.Add(revoke, [options] {
    return WithDirectory(*options, false, [&](MotionStore&, TenantDirectory& directory) {
      auto tenant = directory.FindTenant(options->name);
      if (!tenant.ok()) return ReportError(tenant.status());
      if (absl::Status status = directory.RevokeKey(tenant->id, options->key_id); !status.ok())
        return ReportError(status);
      if (!options->json) std::cout << "key " << options->key_id << " of tenant '" << options->name << "' revoked\n";
      return 0;
    });
  });
}

}  // namespace mocap

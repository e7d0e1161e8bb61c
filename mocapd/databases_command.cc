// `mocapd databases`: the motion databases of a store.
#include <iostream>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "mocapd/commands.h"
#include "storage/motion_store.h"
#include "storage/tenant_directory.h"
#include "tools/command_line/number_format.h"

namespace mocap {
void RegisterDatabasesCommand(CLI::App& app, CommandRegistry& registry) {
  struct Options {
    std::string store;
    std::string tenant;
    bool json = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* command = app.add_subcommand("databases", "List the motion databases of a store");
  command->add_option("--store", options->store, "Motion store file")->required();
  command->add_option("--tenant", options->tenant, "Tenant whose databases to list (default: 'default')");
  command->add_flag("--json", options->json, "Print JSON");
  registry.Add(command, [options] {
    auto store = MotionStore::Open(options->store, StoreOpenOptions{.create_if_missing = false});
    if (!store.ok()) return ReportError(store.status());
    auto tenant = ResolveTenant(**store, options->tenant);
    if (!tenant.ok()) return ReportError(tenant.status());
    auto databases = (*store)->ListDatabases(*tenant);
    if (!databases.ok()) return ReportError(databases.status());
    if (options->json) {
      nlohmann::json out = nlohmann::json::array();
      for (const DatabaseSummary& d : *databases) {
        out.push_back({{"name", d.ref.name()},
                       {"clips", d.num_clips},
                       {"frames", d.num_frames},
                       {"seconds", d.seconds()},
                       {"frame_rate", d.frame_rate},
                       {"unit", std::string(UnitName(d.unit))},
                       {"joints", d.num_joints},
                       {"root_joint", d.root_joint}});
      }
      std::cout << out.dump(2) << "\n";
      return 0;
    }
    if (databases->empty()) std::cout << "no motion databases in " << options->store << "\n";
    for (const DatabaseSummary& d : *databases) {
      if (!d.has_rig) {
        std::cout << d.ref.name() << ": empty (its rig comes with the first import) at " << d.frame_rate << " fps\n";
        continue;
      }
      std::cout << d.ref.name() << ": " << d.num_clips << " clips, " << Thousands(d.num_frames) << " frames ("
                << d.seconds() / 60.0 << " min) at " << d.frame_rate << " fps; rig of " << d.num_joints
                << " joints rooted at " << d.root_joint << ", imported from " << UnitName(d.unit) << "\n";
    }
    return 0;
  });
}

}  // namespace mocap

// `mocap similar`: cross-skeleton similar-pose search on the server (PoseSearch over the SDK);
// the same options and output as `mocapd similar` on a local store (`--json`: the same JSON).
#pragma once

#include <CLI/CLI.hpp>

#include "client/cli/cli_common.h"

namespace mocap::cli {

void RegisterSimilar(CLI::App& app, Registry& registry);

}  // namespace mocap::cli

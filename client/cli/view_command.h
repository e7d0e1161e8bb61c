// `mocap view FILE.bvh [MORE.bvh ...] [RECONSTRUCTION.json ...] [-o view.html]`: one self-contained
// HTML page playing the clips overlaid or side by side (no server needed).
#pragma once

#include <CLI/CLI.hpp>

#include "client/cli/cli_common.h"

namespace mocap::cli {

void RegisterView(CLI::App& app, Registry& registry);

}  // namespace mocap::cli

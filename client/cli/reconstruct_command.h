// `mocap reconstruct`: streams a wrist trajectory (CSV, or a BVH clip's wrists with optional noise)
// through a Reconstruction session and writes the result as BVH and JSON.
#pragma once

#include <CLI/CLI.hpp>

#include "client/cli/cli_common.h"

namespace mocap::cli {

void RegisterReconstruct(CLI::App& app, Registry& registry);

}  // namespace mocap::cli

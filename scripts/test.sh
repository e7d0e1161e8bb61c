#!/usr/bin/env bash
# The README's test command: sets up everything (packages, build) and runs the whole test suite.
# Tests that need ../shared/data unpack it on first use (into ~/.cache/mocap/data) or skip with a
# message when it is absent.
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
"$repo/scripts/setup.sh"
cd "$repo/build"
ctest --output-on-failure -j "$(nproc)" "$@"

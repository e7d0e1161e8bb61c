#!/usr/bin/env bash
# ctest device_log_converters: the device-log converters (tools/converters, docs/devices) on
# synthetic logs of every source, and their CSVs through mocap's own CSV reader when MOCAP_CLI
# (the `mocap` program) is given. Skips (exit code 77) without python3.
#   usage: tests/tools/converters/run_tests.sh [MOCAP_CLI]
set -euo pipefail
if ! command -v python3 >/dev/null 2>&1; then
  echo "skipped: python3 not found (tools/converters and its tests need it)"
  exit 77
fi
mocap=${1:-${MOCAP_CLI:-}}
[ -z "$mocap" ] || mocap=$(realpath "$mocap")
cd "$(dirname "$0")"
MOCAP_CLI=$mocap PYTHONDONTWRITEBYTECODE=1 exec python3 -m unittest discover -s . -p 'test_*.py' -v

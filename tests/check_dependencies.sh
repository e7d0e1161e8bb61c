#!/usr/bin/env bash
# Fails when a folder includes what docs/architecture.md says it must not: motion <- storage
# <- server <- mocapd, proto <- client <- mocap / mocap-load; tools/ serves the tools only.
set -euo pipefail
root=${1:-$(cd "$(dirname "$0")/.." && pwd)}
fail=0
# $1: message, $2: include pattern (extended regex after `#include [<"]`), then folders.
forbid() {
  local message=$1 pattern=$2
  shift 2
  local dirs=()
  for dir in "$@"; do [ -d "$root/$dir" ] && dirs+=("$root/$dir"); done
  [ ${#dirs[@]} -gt 0 ] || return 0
  if grep -rnE "#include [<\"]($pattern)" "${dirs[@]}"; then
    echo "FAIL: $message"
    fail=1
  fi
}
forbid "motion/ is pure: no gRPC, Protobuf, SQLite, spdlog, JSON, CLI or other layers" \
  'grpcpp|grpc/|google/protobuf|mocap/v1/|sqlite3|SQLiteCpp|spdlog|nlohmann|CLI/|storage/|server/|client/|mocapd/|tools/|proto/|eval/|html_view/' motion
forbid "storage/ speaks motion's types: no gRPC, Protobuf, server, tools or clients" \
  'grpcpp|grpc/|google/protobuf|mocap/v1/|server/|client/|mocapd/|tools/|proto/|eval/' storage
forbid "server/ reaches SQLite only through storage/, and never the tools or clients" \
  'sqlite3|SQLiteCpp|mocapd/|client/|tools/command_line|CLI/' server
forbid "client/ talks to the server through the API only: no server, storage or SQLite" \
  'sqlite3|SQLiteCpp|server/|storage/|mocapd/' client
forbid "tools/ serves the tools: no server, storage or SQLite" 'sqlite3|SQLiteCpp|server/|storage/|mocapd/' tools
forbid "proto/convert maps the API to motion's types only" 'sqlite3|SQLiteCpp|server/|storage/|mocapd/|client/|tools/' proto
forbid "installed tools never compile test code" 'tests/' motion storage server mocapd client tools proto eval html_view
[ $fail -eq 0 ] && echo "dependency direction: ok"
exit $fail

#!/usr/bin/env bash
# Fails when a folder includes what docs/architecture.md says it must not: motion <- storage
# <- server <- mocapd, proto <- client <- mocap / mocap-load; tools/ serves the tools only;
# html_view/ (the viewer's pages) and eval/ (mocap-eval) build on motion/ and never on the service.
# The SDK itself (client/include, client/src, client/examples: what `-DMOCAP_SDK_ONLY=ON` builds
# and installs) includes only gRPC, Protobuf, Abseil, the generated mocap/v1/ headers and its own;
# client/'s tools (cli/, load/, wrist_input/) may also use motion/, tools/, html_view/ and
# proto/convert.
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
  'grpcpp|grpc/|google/protobuf|mocap/v1/|server/|client/|mocapd/|tools/|proto/|eval/|html_view/' storage
forbid "server/ reaches SQLite only through storage/, and never the tools, clients, pages or evaluation" \
  'sqlite3|SQLiteCpp|mocapd/|client/|tools/command_line|CLI/|eval/|html_view/' server
forbid "client/ talks to the server through the API only: no server, storage, SQLite or evaluation" \
  'sqlite3|SQLiteCpp|server/|storage/|mocapd/|eval/' client
forbid "the SDK (client/include, src, examples) needs gRPC, Protobuf and Abseil only: no motion, tools or other libraries" \
  'motion/|storage/|server/|mocapd/|tools/|eval/|html_view/|proto/|client/(cli|load|wrist_input)/|sqlite3|SQLiteCpp|spdlog|nlohmann|CLI/|Eigen/|flann/' \
  client/include client/src client/examples
forbid "tools/ serves the tools: no server, storage, SQLite, pages or evaluation" \
  'sqlite3|SQLiteCpp|server/|storage/|mocapd/|eval/|html_view/' tools
forbid "proto/convert maps the API to motion's types only" \
  'sqlite3|SQLiteCpp|server/|storage/|mocapd/|client/|tools/|eval/|html_view/' proto
forbid "html_view/ writes pages of motion's clips: no gRPC, Protobuf, SQLite, service, tools or evaluation" \
  'grpcpp|grpc/|google/protobuf|mocap/v1/|proto/|sqlite3|SQLiteCpp|storage/|server/|client/|mocapd/|tools/|eval/|CLI/' html_view
forbid "eval/ evaluates the motion library offline: no gRPC, Protobuf or service; SQLite only through storage/" \
  'grpcpp|grpc/|google/protobuf|mocap/v1/|proto/|sqlite3|SQLiteCpp|server/|client/|mocapd/' eval
forbid "installed tools never compile test code" 'tests/' motion storage server mocapd client tools proto eval html_view
[ $fail -eq 0 ] && echo "dependency direction: ok"
exit $fail

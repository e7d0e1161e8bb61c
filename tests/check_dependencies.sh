#!/usr/bin/env bash
# Fails when a layer includes what it must not (docs: motion <- storage <- server; motion is pure).
set -euo pipefail
root=${1:-$(cd "$(dirname "$0")/.." && pwd)}
fail=0
if grep -rnE '#include [<"](grpcpp|grpc|google/protobuf|sqlite3|SQLiteCpp|spdlog)' "$root/motion"; then
  echo "motion/ must not depend on gRPC, Protobuf, SQLite or spdlog"; fail=1
fi
if grep -rnE '#include [<"](sqlite3|SQLiteCpp)' "$root/server" "$root/client"; then
  echo "server/ and client/ reach SQLite only through storage/"; fail=1
fi
[ $fail -eq 0 ] && echo "dependency direction: ok"
exit $fail

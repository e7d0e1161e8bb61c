#!/usr/bin/env bash
# PoseSearch over gRPC on the standard database (issue #11): serves a store holding the standard
# split's database takes (`mocapd serve --read-only`, a temporary key) and runs
# mocap_pose_search_rpc_benchmark against it; prints p50/p99 per query frame. Compare with the
# in-process figure: build/benchmarks/mocap_similarity_benchmark --benchmark_counters_tabular=true.
#   usage: benchmarks/pose_search_rpc.sh [BENCHMARK OPTIONS...]
#   env: STORE (var/mocap.db: the quickstart's store; its bandai-namco-2 is the standard database),
#        BUILD (build)
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
build=${BUILD:-$repo/build}
mocapd="$build/mocapd/mocapd"
bench="$build/benchmarks/mocap_pose_search_rpc_benchmark"
store=${STORE:-$repo/var/mocap.db}
[ -f "$store" ] || { echo "no store at $store: run scripts/quickstart.sh first" >&2; exit 2; }
out="$build/pose_search_rpc"
mkdir -p "$out"
# shellcheck source=scripts/temporary_server.sh
source "$repo/scripts/temporary_server.sh"
trap stop_temporary_server EXIT
start_temporary_server "$mocapd" "$store" "$out/server.log" --read-only
"$bench" --address "$address" --database bandai-namco-2 "$@"

#!/usr/bin/env bash
# Bounded memory (issue #14): the server's RSS while one session streams 200,000 samples (a
# report every 20,000 frames: it must stay flat within a few MB), then over 50 sessions in a row
# (it must return to where it started). On the store the quickstart built (the standard split's
# database), with a server of its own.
#   usage: benchmarks/session_memory.sh   env: STORE (var/mocap.db), SAMPLES (200000), LAG (5)
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
mocapd="$repo/build/mocapd/mocapd"
store=${STORE:-$repo/var/mocap.db}
clip="${MOCAP_DATA_CACHE_DIR:-$HOME/.cache/mocap/data}/bandai-namco-2/dataset-2_walk_normal_003.bvh"
out="$repo/build/memory"
[ -f "$store" ] || { echo "no store at $store: run scripts/quickstart.sh first" >&2; exit 2; }
[ -f "$clip" ] || { echo "no held-out clip at $clip: run scripts/quickstart.sh (it unpacks the data) first" >&2; exit 2; }
mkdir -p "$out"
# shellcheck source=scripts/temporary_server.sh
source "$repo/scripts/temporary_server.sh"
trap stop_temporary_server EXIT
start_temporary_server "$mocapd" "$store" "$out/server.log" --read-only
"$repo/build/benchmarks/mocap_session_memory" --address "$address" --database bandai-namco-2 --bvh "$clip" \
  --server-pid "$temporary_server_pid" --samples "${SAMPLES:-200000}" --lag "${LAG:-5}"

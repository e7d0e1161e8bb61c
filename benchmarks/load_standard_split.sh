#!/usr/bin/env bash
# The service's load figure (issue: ≥ 20 concurrent 30 Hz streams at p99 ≤ 50 ms of processing
# latency on the standard database): a `mocapd serve --read-only` on the store the quickstart
# built (bandai-namco-2 = the standard split's database takes), then mocap-load with each stream
# count in turn, each stream replaying a held-out walk's wrists (FK + 0.5 cm noise) in real time.
#   usage: benchmarks/load_standard_split.sh [STREAMS...]   (default: 5 10 20 30)
#   env: STORE (var/mocap.db), SECONDS_PER_RUN (30), LAG (0), EXTRA (more mocap-load options),
#        SERVER_EXTRA (more mocapd serve options, e.g. --no-reversed-motion)
# Prints one line per run and writes build/load/streams-N.json (mocap-load --json).
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
mocapd="$repo/build/mocapd/mocapd"
load="$repo/build/client/mocap-load"
store=${STORE:-$repo/var/mocap.db}
data="${MOCAP_DATA_CACHE_DIR:-$HOME/.cache/mocap/data}/bandai-namco-2"
clip="$data/dataset-2_walk_normal_003.bvh"
out="$repo/build/load"
[ -f "$store" ] || { echo "no store at $store: run scripts/quickstart.sh first" >&2; exit 2; }
[ -f "$clip" ] || { echo "no held-out clip at $clip: run scripts/quickstart.sh (it unpacks the data) first" >&2; exit 2; }
mkdir -p "$out"
streams=("$@")
[ ${#streams[@]} -gt 0 ] || streams=(5 10 20 30)

# A key of its own, revoked at the end: the store is written only by those two admin commands.
# shellcheck source=scripts/temporary_server.sh
source "$repo/scripts/temporary_server.sh"
trap stop_temporary_server EXIT
# shellcheck disable=SC2086  # SERVER_EXTRA is a list of options
start_temporary_server "$mocapd" "$store" "$out/server.log" --read-only ${SERVER_EXTRA:-}

# One short session first, so the database's indices are built before any timing.
"$load" --address "$address" --database bandai-namco-2 --bvh "$clip" --streams 1 --seconds 1 \
  --json >/dev/null
for n in "${streams[@]}"; do
  # shellcheck disable=SC2086  # EXTRA is a list of options
  "$load" --address "$address" --database bandai-namco-2 --bvh "$clip" --streams "$n" \
    --seconds "${SECONDS_PER_RUN:-30}" --lag "${LAG:-0}" --json ${EXTRA:-} >"$out/streams-$n.json" || true
  python3 - "$out/streams-$n.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
l = r["latency_ms"]
print(f'{r["streams"]:3d} streams: {r["streams_ok"]} ok, {r["frames_per_second"]:6.1f} frames/s, latency ms '
      f'p50 {l["p50"]:.1f} p90 {l["p90"]:.1f} p99 {l["p99"]:.1f} max {l["max"]:.1f}, server reply ms mean '
      f'{r["server_reply_ms"]["mean"]:.1f} (pipeline per frame {r["server_stage_ms_per_frame"]["pipeline"]:.2f}), '
      f'worst late send {r["worst_late_send_ms"]:.0f} ms, errors {r["errors"] or 0}')
print('    p99 ms by second of the run: ' +
      ' '.join(f'{s["p99"]:.0f}' if s["count"] else '-' for s in r.get("latency_by_second_ms", [])))
PY
done

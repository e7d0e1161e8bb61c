#!/usr/bin/env bash
# Fair sharing of the compute pool (issue #14): a victim tenant's real-time session, measured with
# mocap-load alone and then beside another tenant's flood: 64 sessions (that tenant's limit)
# sending samples at 1 kHz, each as large messages, which saturate the server many times over.
# The victim's p99 frame latency must stay ≤ 50 ms.
#   usage: benchmarks/fairness_flood.sh
#   env: SECONDS_PER_RUN (20), FLOOD_STREAMS (64), FLOOD_RATE (1000), K1 (default: the server's)
# Builds its own store in build/fairness (two tenants, each with the standard split's database).
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
mocapd="$repo/build/server/mocapd"
load="$repo/build/client/mocap-load"
data="${MOCAP_DATA_CACHE_DIR:-$HOME/.cache/mocap/data}"
out="$repo/build/fairness"
seconds=${SECONDS_PER_RUN:-20}
"$repo/../shared/data/unpack.sh" "$data" bandai-namco-2 >/dev/null
clip="$data/bandai-namco-2/dataset-2_walk_normal_003.bvh"
rm -rf "$out" && mkdir -p "$out"
store="$out/store.db"
for tenant in victim flood; do
  "$mocapd" tenant create --store "$store" "$tenant" >/dev/null
  find "$data/bandai-namco-2" -name '*.bvh' ! -name '*3.bvh' -print0 | sort -z \
    | xargs -0 "$mocapd" import --quiet --store "$store" --tenant "$tenant" --database walks >/dev/null
done
victim_key=$("$mocapd" tenant add-key --store "$store" victim 2>/dev/null)
flood_key=$("$mocapd" tenant add-key --store "$store" flood 2>/dev/null)
coproc SERVER { exec "$mocapd" serve --store "$store" --listen 127.0.0.1:0 2>"$out/server.log"; }
server_pid=$SERVER_PID
trap 'kill $server_pid 2>/dev/null; wait $server_pid 2>/dev/null || true' EXIT
read -r -t 60 line <&"${SERVER[0]}"
address=${line#listening on }
k1=(); [ -n "${K1:-}" ] && k1=(--k1 "$K1")

victim() {  # $1: label
  "$load" --address "$address" --key "$victim_key" --database walks --bvh "$clip" --streams 1 --seconds "$seconds" \
    "${k1[@]}" --json >"$out/victim-$1.json" || true
  python3 - "$out/victim-$1.json" "$1" <<'PY'
import json, sys
r = json.load(open(sys.argv[1])); l = r["latency_ms"]
print(f'victim {sys.argv[2]:12s}: {r["streams_ok"]}/{r["streams"]} ok, {r["frames_per_second"]:5.1f} frames/s, '
      f'latency ms p50 {l["p50"]:.1f} p90 {l["p90"]:.1f} p99 {l["p99"]:.1f} max {l["max"]:.1f}, errors {r["errors"] or 0}')
PY
}

# Warm-up: both tenants' indices built before any timing.
for key in "$victim_key" "$flood_key"; do
  "$load" --address "$address" --key "$key" --database walks --bvh "$clip" --streams 1 --seconds 1 --json >/dev/null
done
victim alone
"$load" --address "$address" --key "$flood_key" --database walks --bvh "$clip" --streams "${FLOOD_STREAMS:-64}" \
  --rate "${FLOOD_RATE:-1000}" --seconds $((seconds + 10)) "${k1[@]}" --json >"$out/flood.json" 2>/dev/null &
flood_pid=$!
sleep 5  # the flood is running at full strength
victim "beside-flood"
wait "$flood_pid" || true
python3 - "$out/flood.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1])); l = r["latency_ms"]
print(f'flood              : {r["streams_ok"]}/{r["streams"]} ok, {r["frames_per_second"]:6.1f} frames/s over all its '
      f'streams, latency ms p50 {l["p50"]:.0f} p99 {l["p99"]:.0f}, errors {r["errors"] or 0}')
PY

#!/usr/bin/env bash
# The server's CPU per reconstruction session start (issue #24: another tenant's session churn
# costs a live stream what each start costs the shared pool). Streams of the flood tenant open a
# session, send one sample a second (next to no frame work) and cancel it after 0.1 s, again
# and again; the server's user + system CPU over the run, divided by the sessions opened, is what
# one start costs: connection, authentication, the database lookup and the session's setup.
#   usage: benchmarks/session_start_cost.sh   (after benchmarks/fairness_flood.sh has built its store)
#   env: STORE (build/fairness/store.db: tenant "flood", database "walks"), SECONDS_PER_RUN (20), STREAMS (4)
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
mocapd="$repo/build/mocapd/mocapd"
load="$repo/build/client/mocap-load"
store=${STORE:-$repo/build/fairness/store.db}
data="${MOCAP_DATA_CACHE_DIR:-$HOME/.cache/mocap/data}"
clip="$data/bandai-namco-2/dataset-2_walk_normal_003.bvh"
[ -f "$store" ] || { echo "no store at $store: run benchmarks/fairness_flood.sh first (it builds one)" >&2; exit 1; }
source "$repo/scripts/temporary_server.sh"
log=$(mktemp)
key=$("$mocapd" tenant add-key --store "$store" flood 2>/dev/null)
trap 'stop_temporary_server; "$mocapd" tenant revoke-key --store "$store" flood "$key" >/dev/null 2>&1 || true; rm -f "$log"' EXIT
start_temporary_server "$mocapd" "$store" "$log"
server_pid=$temporary_server_pid
# Warm-up: the database's index is built before the count starts.
"$load" --address "$address" --key "$key" --database walks --bvh "$clip" --streams 1 --seconds 1 --json >/dev/null
cpu_ticks() { awk '{print $14 + $15}' "/proc/$server_pid/stat"; }
before=$(cpu_ticks)
result=$(mktemp)
"$load" --address "$address" --key "$key" --database walks --bvh "$clip" --streams "${STREAMS:-4}" \
  --seconds "${SECONDS_PER_RUN:-20}" --reopen-after 0.1 --rate 1 --json >"$result"
after=$(cpu_ticks)
python3 - "$result" "$before" "$after" "$(getconf CLK_TCK)" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
seconds = (int(sys.argv[3]) - int(sys.argv[2])) / int(sys.argv[4])
sessions = max(1, r["sessions"])
print(f"{r['sessions']} sessions opened and cancelled; server CPU {seconds:.2f} s: "
      f"{1000 * seconds / sessions:.1f} ms per session start; errors {r['errors'] or 0}")
PY
rm -f "$result"

#!/usr/bin/env bash
# Two `mocapd serve` replicas over one store behind nginx (the gRPC load balancer of
# docker/compose.yaml, configured from the same template docker/nginx-grpc.conf), all on 127.0.0.1.
#   usage: two_replicas_test.sh MOCAPD MOCAP
# Checks, through nginx only:
#   - MotionStore calls work (databases list) and an import larger than nginx's default 1 MiB
#     request body limit goes through (client_max_body_size);
#   - several Reconstruct sessions (bidirectional streams), sequential and concurrent, all end OK
#     with every frame back;
#   - BOTH replicas served sessions (their logs' `session=... started` lines, and nginx's access log
#     of which upstream took each call), and each session stayed on one replica from `started` to
#     `ended` (sticky streams);
#   - with one replica stopped, new sessions go to the other; a session sent at the samples' own
#     pace lasts as long on the replica (nginx streams the request through, it does not buffer it).
# MOCAP_KEEP_TEST_DIR=1 keeps the temp dir (logs, nginx config, outputs).
# Skips (exit code 77) when nginx is not installed or no python3 is found (it writes the synthetic
# walks). Needs no shared data: the clips are synthetic walks (tests/deploy/synthetic_walk.py).
set -euo pipefail
mocapd=${1:?usage: two_replicas_test.sh MOCAPD MOCAP}
mocap=${2:?usage: two_replicas_test.sh MOCAPD MOCAP}
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
template=${MOCAP_NGINX_TEMPLATE:-$root/docker/nginx-grpc.conf}
# shellcheck source=tests/deploy/test_lib.sh
source "$here/test_lib.sh"

nginx=${MOCAP_NGINX:-$(command -v nginx || echo /usr/sbin/nginx)}
[ -x "$nginx" ] || skip "nginx is not installed (apt-get install nginx; scripts/setup.sh installs it)"
python=$(python_with json) || skip "no python3 found (it writes the synthetic test clips)"
[ -x "$mocapd" ] || fail "no mocapd at $mocapd"
[ -x "$mocap" ] || fail "no mocap at $mocap"
[ -f "$template" ] || fail "no nginx template at $template"
sessions=${MOCAP_DEPLOY_SESSIONS:-6}

test_lib_init two-replicas
dir=$test_lib_dir
note "temp dir $dir; $("$nginx" -v 2>&1)"

# 1. A store with a tenant, a key and a database of synthetic walks (built offline, as a store
#    file for a deployment is: docs/deployment.md "Scaling out").
store="$dir/store/mocap.db"
mkdir -p "$dir/store" "$dir/clips" "$dir/out"
"$mocapd" tenant create acme --store "$store" >/dev/null
key=$("$mocapd" tenant add-key acme --store "$store" 2>/dev/null)
[[ $key == mk_* ]] || fail "tenant add-key printed '$key', not a key"
clips=()
for spec in "90 1.0 120" "120 1.1 115" "150 0.95 125" "120 1.05 110"; do
  read -r frames cycle speed <<<"$spec"
  clip="$dir/clips/walk_${frames}_${cycle}.bvh"
  "$python" "$here/synthetic_walk.py" bvh "$clip" --frames "$frames" --cycle "$cycle" --speed "$speed"
  clips+=("$clip")
done
timeout 120 "$mocapd" import --store "$store" --tenant acme --database walks --quiet "${clips[@]}" >"$dir/import.txt" ||
  fail "mocapd import failed: $(cat "$dir/import.txt")"
note "store: $(tr '\n' ' ' <"$dir/import.txt")"
# The wrists of another walk (other phase, speed and cycle), as a tracker would send them.
"$python" "$here/synthetic_walk.py" csv "$dir/wrists.csv" --frames 60 --cycle 1.02 --speed 118 --start 0.3
samples=$(($(wc -l <"$dir/wrists.csv") - 1))

# 2. Two read-only replicas over the one store file (as docker/compose.yaml runs them).
start_mocapd "$mocapd" "$store" replica1 --read-only
replica1=$server_address
replica1_pid=$server_pid
start_mocapd "$mocapd" "$store" replica2 --read-only
replica2=$server_address
note "replicas on $replica1 and $replica2"

# 3. nginx from the template: its upstream is the two replicas; pid, logs and temp files in $dir.
mkdir -p "$dir/nginx"
user_line=""
[ "$(id -u)" -ne 0 ] || user_line="user root root;"  # as root, workers would switch to nobody
start_nginx() {
  nginx_port=$(free_port) || fail "no free port for nginx"
  sed -e "s|\${MOCAP_LISTEN}|127.0.0.1:$nginx_port|g" -e "s|\${MOCAP_REPLICA_1}|$replica1|g" \
      -e "s|\${MOCAP_REPLICA_2}|$replica2|g" "$template" >"$dir/nginx/mocap-grpc.conf"
  # shellcheck disable=SC2016  # a literal ${MOCAP_
  ! grep -v '^[[:space:]]*#' "$dir/nginx/mocap-grpc.conf" | grep '\${MOCAP_' || fail "template variables left unreplaced"
  cat >"$dir/nginx/nginx.conf" <<EOF
# Written by tests/deploy/two_replicas_test.sh: the test's process settings around the template.
$user_line
daemon off;
worker_processes 1;
pid $dir/nginx/nginx.pid;
error_log $dir/nginx/error.log info;
events { worker_connections 256; }
http {
    log_format grpc '\$remote_addr "\$request" \$status upstream=\$upstream_addr '
                    'grpc_status=\$upstream_trailer_grpc_status ms=\$request_time';
    access_log $dir/nginx/access.log grpc;
    client_body_temp_path $dir/nginx/client_body;
    proxy_temp_path $dir/nginx/proxy;
    fastcgi_temp_path $dir/nginx/fastcgi;
    uwsgi_temp_path $dir/nginx/uwsgi;
    scgi_temp_path $dir/nginx/scgi;
    include $dir/nginx/mocap-grpc.conf;
}
EOF
  "$nginx" -t -q -p "$dir/nginx/" -e "$dir/nginx/error.log" -c "$dir/nginx/nginx.conf" ||
    fail "nginx -t refused the configuration"
  spawn nginx "$dir/nginx/stdout.log" "$dir/nginx/stderr.log" \
    "$nginx" -p "$dir/nginx/" -e "$dir/nginx/error.log" -c "$dir/nginx/nginx.conf"
  nginx_pid=$spawned_pid
  # Listening once a TCP connection succeeds (bounded: 10 s).
  for _ in $(seq 1 100); do
    alive "$nginx_pid" || return 1
    if (exec 3<>"/dev/tcp/127.0.0.1/$nginx_port") 2>/dev/null; then return 0; fi
    sleep 0.1
  done
  return 1
}
started_nginx=0
for attempt in 1 2 3; do  # the free port may be taken in between: try another
  if start_nginx; then started_nginx=1; break; fi
  note "nginx did not start on port $nginx_port (attempt $attempt): $(tail -n 2 "$dir/nginx/error.log" 2>/dev/null)"
  stop_pid "$nginx_pid" 5
done
[ $started_nginx = 1 ] || fail "nginx did not start"
lb="127.0.0.1:$nginx_port"
note "nginx on $lb"
client=(timeout 120 "$mocap" --address "$lb" --key "$key")

# 4. MotionStore through nginx: the database; an import reaches a replica, which refuses it
#    (read-only store) — not nginx.
"${client[@]}" databases list --json >"$dir/out/databases.json" || fail "databases list through nginx failed"
grep -q '"walks"' "$dir/out/databases.json" || fail "databases list through nginx lacks 'walks'"
! "${client[@]}" import --database walks "${clips[0]}" >/dev/null 2>"$dir/out/import.err" ||
  fail "an import through nginx into the read-only replicas succeeded"
grep -q "read-only store" "$dir/out/import.err" || fail "the import was not refused by a replica: $(cat "$dir/out/import.err")"

# 5. Reconstruct sessions through nginx: first sequential, then two at a time.
run_session() {
  local i=$1
  shift
  "${client[@]}" reconstruct --database walks --csv "$dir/wrists.csv" --lag 4 --k1 60 --k2 40 --diagnostics \
    --samples-per-message 5 --quiet --json -o "$dir/out/session$i" "$@" >"$dir/out/session$i.summary.json" \
    2>"$dir/out/session$i.err"
}
check_session() {
  local i=$1
  "$python" - "$dir/out/session$i.json" "$samples" <<'EOF' || fail "session $i: $(cat "$dir/out/session$i.err")"
import json, sys
result = json.load(open(sys.argv[1]))
frames, samples = result.get("frames", []), int(sys.argv[2])
assert len(frames) == samples, f"{len(frames)} frames for {samples} samples"
assert [f["index"] for f in frames] == list(range(samples)), "frame indices not 0..n-1"
assert int(result["summary"]["frames"]) == samples, result["summary"]
assert all(len(f["rotations"]) == len(result["started"]["skeleton"]["joints"]) for f in frames)
EOF
}
sequential=$((sessions / 2))
for i in $(seq 1 "$sequential"); do
  run_session "$i" || fail "session $i through nginx failed: $(cat "$dir/out/session$i.err")"
  check_session "$i"
done
pids=()
for i in $(seq $((sequential + 1)) "$sessions"); do
  run_session "$i" &
  pids+=("$!")
done
for n in "${!pids[@]}"; do
  i=$((sequential + 1 + n))
  wait "${pids[$n]}" || fail "concurrent session $i through nginx failed: $(cat "$dir/out/session$i.err")"
  check_session "$i"
done
note "$sessions sessions through nginx ended OK with $samples frames each"

# 6. Who served them: both replicas started sessions, and each session ended on the replica that
#    started it (sticky streams). Session ids carry a random per-process tag (TAG-s1, TAG-s2, ...),
#    so no two replicas share one; the clients' ids must be exactly the union of the replicas'.
count1=$(grep -c 'session=.* started' "$dir/replica1.log" || true)
count2=$(grep -c 'session=.* started' "$dir/replica2.log" || true)
note "sessions started: replica1 $count1, replica2 $count2"
[ $((count1 + count2)) -eq "$sessions" ] || fail "$((count1 + count2)) sessions started on the replicas, not $sessions"
if [ "$count1" -lt 1 ] || [ "$count2" -lt 1 ]; then
  fail "one replica served no session (replica1 $count1, replica2 $count2)"
fi
for replica in replica1 replica2; do
  started=$(sed -n 's/.*session=\([^ ]*\) .*started.*/\1/p' "$dir/$replica.log" | sort)
  ended=$(sed -n 's/.*session=\([^ ]*\) request=[^ ]* ended code=.*/\1/p' "$dir/$replica.log" | sort)
  [ "$started" = "$ended" ] || fail "$replica: sessions started ($started) are not those that ended there ($ended)"
  echo "$started" >>"$dir/out/replica_session_ids.txt"
done
for i in $(seq 1 "$sessions"); do
  "$python" -c 'import json,sys; print(json.load(open(sys.argv[1]))["session_id"])' "$dir/out/session$i.summary.json"
done | sort >"$dir/out/client_session_ids.txt"
[ -z "$(sort "$dir/out/replica_session_ids.txt" | uniq -d)" ] ||
  fail "two replicas handed out the same session id: $(sort "$dir/out/replica_session_ids.txt" | uniq -d | tr '\n' ' ')"
sort "$dir/out/replica_session_ids.txt" | diff - "$dir/out/client_session_ids.txt" >/dev/null ||
  fail "the clients' session ids ($(tr '\n' ' ' <"$dir/out/client_session_ids.txt")) are not the replicas'"
# nginx's side: the Reconstruct calls went to both upstreams, each answered grpc-status 0.
grep 'Reconstruct ' "$dir/nginx/access.log" >"$dir/out/reconstruct_calls.log" || true
[ "$(wc -l <"$dir/out/reconstruct_calls.log")" -eq "$sessions" ] ||
  fail "nginx logged $(wc -l <"$dir/out/reconstruct_calls.log") Reconstruct calls, not $sessions"
[ "$(grep -c "upstream=$replica1 " "$dir/out/reconstruct_calls.log" || true)" -eq "$count1" ] ||
  fail "nginx's calls to replica1 ($replica1) are not the $count1 sessions replica1 logged"
[ "$(grep -c "upstream=$replica2 " "$dir/out/reconstruct_calls.log" || true)" -eq "$count2" ] ||
  fail "nginx's calls to replica2 ($replica2) are not the $count2 sessions replica2 logged"
! grep -v 'grpc_status=0 ' "$dir/out/reconstruct_calls.log" || fail "a Reconstruct call did not end with grpc-status 0"
note "nginx: $(grep -c "upstream=$replica1 " "$dir/out/reconstruct_calls.log") calls to $replica1," \
  "$(grep -c "upstream=$replica2 " "$dir/out/reconstruct_calls.log") to $replica2"

# 7. A replica going away: new calls go to the other one (nginx tries the next upstream when the
#    connection is refused), and the survivor serves them. The second session sends its samples at
#    their timestamps' pace (--realtime, 2 s): the replica must see the call last about that long,
#    i.e. nginx streams the request through instead of buffering it until the client half-closes.
kill -TERM "$replica1_pid"
for _ in $(seq 1 100); do alive "$replica1_pid" || break; sleep 0.1; done
! alive "$replica1_pid" || fail "replica1 did not stop within 10 s of SIGTERM"
before2=$(grep -c 'session=.* started' "$dir/replica2.log" || true)
i=$((sessions + 1))
run_session "$i" || fail "session $i with replica1 down failed: $(cat "$dir/out/session$i.err")"
check_session "$i"
i=$((sessions + 2))
run_session "$i" --realtime || fail "realtime session $i with replica1 down failed: $(cat "$dir/out/session$i.err")"
check_session "$i"
after2=$(grep -c 'session=.* started' "$dir/replica2.log" || true)
[ $((after2 - before2)) -eq 2 ] || fail "with replica1 down, replica2 started $((after2 - before2)) sessions, not 2"
note "with replica1 stopped, both new sessions went to replica2"
span=$("$python" -c 'import csv,sys; t=[float(r["time"]) for r in csv.DictReader(open(sys.argv[1]))]; print(t[-1]-t[0])' \
  "$dir/wrists.csv")
call_ms=$(grep 'method=Reconstruct ' "$dir/replica2.log" | tail -n 1 | sed -n 's/.* ms=\([0-9.]*\).*/\1/p')
"$python" -c 'import sys; sys.exit(0 if float(sys.argv[1]) >= 0.75 * 1000 * float(sys.argv[2]) else 1)' \
  "${call_ms:-0}" "$span" ||
  fail "the realtime session lasted ${call_ms:-?} ms on the replica for ${span} s of samples: nginx buffered the stream"
note "realtime session: ${call_ms} ms on the replica for ${span} s of samples (streamed through, not buffered)"

# 8. A call whose request stream exceeds 1 MiB (nginx's default client_max_body_size would answer
# 413, which gRPC clients see as an error): a long session of samples, nearest-neighbour method.
"$python" "$here/synthetic_walk.py" csv "$dir/long_wrists.csv" --frames 24000 --cycle 1.2 --speed 100
"${client[@]}" reconstruct --database walks --csv "$dir/long_wrists.csv" --method nearest --samples-per-message 1000 \
  --quiet --json -o "$dir/out/long" >"$dir/out/long.summary.json" 2>"$dir/out/long.err" ||
  fail "a session of 24000 samples through nginx failed: $(cat "$dir/out/long.err")"
grep -q '"frames": "24000"' "$dir/out/long.summary.json" || fail "the long session did not return 24000 frames: $(cat "$dir/out/long.summary.json")"
note "a 24000-sample session (over 1 MiB of request stream) went through nginx"
echo "PASS: two replicas behind nginx"

# shellcheck shell=bash
# Shell helpers of the deployment and interop tests (sourced, not run): a temp dir, processes that
# are always stopped on exit, `mocapd serve` on a free loopback port, bounded waits, skipping.
# Every process started through these helpers is stopped by the EXIT trap, by its own pid.

skip() { echo "SKIP: $*"; exit 77; }
fail() { echo "FAIL: $*" >&2; exit 1; }
note() { echo "[$(date +%H:%M:%S)] $*"; }

test_lib_pids=()
test_lib_dir=""
test_lib_keep=${MOCAP_KEEP_TEST_DIR:-0}

# Whether a process runs (a child that exited but was not waited for is a zombie: not running).
alive() {
  local state
  state=$(ps -o stat= -p "$1" 2>/dev/null) || return 1
  [[ $state != Z* ]]
}

# SIGTERM, then at most SECONDS (default 10) for it to exit, then SIGKILL; reaps it.
#   stop_pid PID [SECONDS]
stop_pid() {
  local pid=$1 seconds=${2:-10}
  kill -TERM "$pid" 2>/dev/null || true
  for _ in $(seq 1 $((seconds * 10))); do alive "$pid" || break; sleep 0.1; done
  kill -KILL "$pid" 2>/dev/null || true
  wait "$pid" 2>/dev/null || true
}

test_lib_cleanup() {
  local status=$?
  local pid
  for pid in "${test_lib_pids[@]}"; do
    kill -TERM "$pid" 2>/dev/null || true
  done
  for pid in "${test_lib_pids[@]}"; do
    # Bounded: SIGKILL after 10 s (mocapd drains its calls for --drain-seconds first).
    stop_pid "$pid" 10
  done
  if [ -n "$test_lib_dir" ] && [ -d "$test_lib_dir" ]; then
    if [ "$status" -ne 0 ] && [ "$status" -ne 77 ]; then
      # On failure, show the logs that explain it, then keep or remove the dir.
      local log
      for log in "$test_lib_dir"/*.log "$test_lib_dir"/nginx/*.log; do
        [ -f "$log" ] || continue
        echo "----- ${log#"$test_lib_dir"/} (last 40 lines)"
        tail -n 40 "$log"
      done
    fi
    if [ "$test_lib_keep" = 1 ]; then echo "kept $test_lib_dir"; else rm -rf "$test_lib_dir"; fi
  fi
  exit "$status"
}

# Makes the temp dir ($test_lib_dir) and installs the cleanup trap.
test_lib_init() {
  test_lib_dir=$(mktemp -d "${TMPDIR:-/tmp}/mocap-${1:-test}.XXXXXX")
  trap test_lib_cleanup EXIT
  trap 'exit 130' INT TERM
}

# Runs a command in the background with its stdout and stderr in files; records its pid.
#   spawn NAME OUT ERR COMMAND...   (sets $spawned_pid)
spawn() {
  local out=$2 err=$3
  shift 3
  "$@" >"$out" 2>"$err" &
  spawned_pid=$!
  test_lib_pids+=("$spawned_pid")
}

# Waits (at most SECONDS) until FILE holds a line matching REGEX; prints the line.
#   wait_for_line FILE REGEX SECONDS PID
wait_for_line() {
  local file=$1 regex=$2 seconds=$3 pid=${4:-}
  local deadline=$((SECONDS + seconds))
  while [ $SECONDS -lt $deadline ]; do
    if grep -Eq -- "$regex" "$file" 2>/dev/null; then
      grep -Em1 -- "$regex" "$file"
      return 0
    fi
    if [ -n "$pid" ] && ! alive "$pid"; then return 1; fi
    sleep 0.1
  done
  return 1
}

# Starts `mocapd serve --store STORE --listen 127.0.0.1:0 EXTRA...` with its log in NAME.log and
# sets $server_address (127.0.0.1:PORT, from its one stdout line) and $server_pid.
#   start_mocapd MOCAPD STORE NAME [EXTRA...]
start_mocapd() {
  local mocapd=$1 store=$2 name=$3
  shift 3
  spawn "$name" "$test_lib_dir/$name.out" "$test_lib_dir/$name.log" \
    "$mocapd" serve --store "$store" --listen 127.0.0.1:0 --drain-seconds 2 "$@"
  server_pid=$spawned_pid
  local line
  line=$(wait_for_line "$test_lib_dir/$name.out" '^listening on 127\.0\.0\.1:[0-9]+$' 30 "$server_pid") ||
    fail "$name: mocapd serve did not print 'listening on 127.0.0.1:PORT' within 30 s"
  # shellcheck disable=SC2034  # for the caller
  server_address=${line#listening on }
}

# A TCP port on 127.0.0.1 that was free a moment ago (the caller retries if it is taken since).
free_port() {
  local port
  for _ in $(seq 1 50); do
    port=$((20000 + RANDOM % 30000))
    if ! (exec 3<>"/dev/tcp/127.0.0.1/$port") 2>/dev/null; then echo "$port"; return 0; fi
  done
  return 1
}

# The first Python 3 interpreter that imports every module named: $MOCAP_PYTHON, then Debian's
# /usr/bin/python3 (where python3-grpcio and python3-protobuf install), then python3 on PATH.
#   python_with MODULE...   (prints the interpreter, or fails)
python_with() {
  local candidate imports
  imports=$(printf 'import %s;' "$@")
  for candidate in ${MOCAP_PYTHON:-} /usr/bin/python3 python3; do
    command -v "$candidate" >/dev/null 2>&1 || continue
    if "$candidate" -c "$imports" >/dev/null 2>&1; then command -v "$candidate"; return 0; fi
  done
  return 1
}

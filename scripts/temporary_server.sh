# Sourced by scripts that drive a local server (quickstart.sh, benchmarks/load_standard_split.sh):
#   start_temporary_server MOCAPD STORE LOG [SERVE_OPTIONS...]
# starts `mocapd serve` on STORE at a free loopback port with a fresh API key of the local tenant
# ("default", the tenant the local import commands act as), sets `address` and exports
# MOCAP_API_KEY (which mocap and mocap-load read). stop_temporary_server stops it and revokes the
# key; callers run it on EXIT.
start_temporary_server() {
  temporary_mocapd=$1 temporary_store=$2
  local log=$3 line
  shift 3
  temporary_key=$("$temporary_mocapd" tenant add-key --store "$temporary_store" default 2>/dev/null)
  export MOCAP_API_KEY=$temporary_key
  coproc TEMPORARY_SERVER { exec "$temporary_mocapd" serve --store "$temporary_store" --listen 127.0.0.1:0 "$@" 2>"$log"; }
  temporary_server_pid=$TEMPORARY_SERVER_PID
  read -r -t 60 line <&"${TEMPORARY_SERVER[0]}" || { echo "mocapd serve did not start; see $log" >&2; return 1; }
  address=${line#listening on }
}

stop_temporary_server() {
  if [ -n "${temporary_server_pid:-}" ]; then
    kill "$temporary_server_pid" 2>/dev/null && wait "$temporary_server_pid" 2>/dev/null || true
  fi
  if [ -n "${temporary_key:-}" ]; then  # revoke-key takes the key itself (it keeps the mk_xxxxxxxx id)
    "$temporary_mocapd" tenant revoke-key --store "$temporary_store" default "$temporary_key" >/dev/null 2>&1 || true
  fi
}

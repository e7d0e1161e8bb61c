#!/usr/bin/env bash
# The Reconstruction and PoseSearch services from Python's grpcio against the C++ SDK
# (python_reconstruct_test.py, python_pose_search_test.py).
#   usage: python_reconstruct_test.sh MOCAPD MOCAP STUB_DIR
# Generates the Python stubs of proto/mocap/v1/*.proto into STUB_DIR (in the build dir; generated
# code is never committed) with protoc and grpc_python_plugin (Debian: protobuf-compiler,
# protobuf-compiler-grpc) when available, else `python3 -m grpc_tools.protoc`; starts one
# `mocapd serve` on 127.0.0.1 over a store of synthetic walks; reconstructs a wrist CSV with
# `mocap reconstruct --csv ... --json` (C++ SDK); then runs the Python client on the same CSV and
# config and compares; then searches similar poses of another walk with `mocap similar
# --json` (C++ SDK) and from Python, and compares. Skips (exit code 77) without a python3 that has grpc and google.protobuf
# (Debian: python3-grpcio, python3-protobuf) or without a stub generator.
set -euo pipefail
mocapd=${1:?usage: python_reconstruct_test.sh MOCAPD MOCAP STUB_DIR}
mocap=${2:?usage: python_reconstruct_test.sh MOCAPD MOCAP STUB_DIR}
stubs=${3:?usage: python_reconstruct_test.sh MOCAPD MOCAP STUB_DIR}
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
# shellcheck source=tests/deploy/test_lib.sh
source "$root/tests/deploy/test_lib.sh"

python=$(python_with grpc google.protobuf) ||
  skip "no python3 with grpc and google.protobuf (apt-get install python3-grpcio python3-protobuf)"
[ -x "$mocapd" ] || fail "no mocapd at $mocapd"
[ -x "$mocap" ] || fail "no mocap at $mocap"

# 1. Python stubs, generated afresh into the build dir.
case "$stubs" in
  */python_stubs | */python_stubs/) ;;
  *) fail "STUB_DIR must end in python_stubs (it is emptied first): $stubs" ;;
esac
rm -rf "$stubs" && mkdir -p "$stubs"
protos=("$root"/proto/mocap/v1/*.proto)
# The system's protoc and plugin first: they match the system's protobuf runtime, and Debian's
# python3-grpc-tools bundles a protoc (3.5.1) too old for the protos' `optional` fields.
generated=""
if command -v protoc >/dev/null && command -v grpc_python_plugin >/dev/null; then
  protoc -I "$root/proto" --python_out="$stubs" --grpc_python_out="$stubs" \
    --plugin=protoc-gen-grpc_python="$(command -v grpc_python_plugin)" "${protos[@]}"
  generator="protoc $(protoc --version | awk '{print $2}') + grpc_python_plugin"
  generated=yes
elif "$python" -c 'import grpc_tools.protoc' >/dev/null 2>&1; then
  if "$python" -m grpc_tools.protoc -I "$root/proto" --python_out="$stubs" --grpc_python_out="$stubs" \
    "${protos[@]}"; then
    generator="grpc_tools.protoc"
    generated=yes
  else
    skip "grpc_tools.protoc could not compile the protos (an old bundled protoc rejects 'optional' fields): apt-get install protobuf-compiler protobuf-compiler-grpc"
  fi
fi
[ -n "$generated" ] ||
  skip "no Python stub generator (protoc with grpc_python_plugin from protobuf-compiler-grpc, or grpc_tools)"
[ -f "$stubs/mocap/v1/reconstruction_pb2_grpc.py" ] || fail "stub generation made no reconstruction_pb2_grpc.py"
"$python" -c "import sys; sys.path.insert(0, sys.argv[1]); import mocap.v1.reconstruction_pb2_grpc" "$stubs" ||
  fail "the generated stubs do not import (protobuf runtime $("$python" -c 'import google.protobuf as p; print(p.__version__)'))"

test_lib_init python-interop
dir=$test_lib_dir
note "python $python (grpcio $("$python" -c 'import grpc; print(grpc.__version__)')), stubs by $generator in $stubs"

# 2. A store of synthetic walks and the wrists of another walk.
store="$dir/mocap.db"
mkdir -p "$dir/clips"
"$mocapd" tenant create acme --store "$store" >/dev/null
key=$("$mocapd" tenant add-key acme --store "$store" 2>/dev/null)
[[ $key == mk_* ]] || fail "tenant add-key printed '$key', not a key"
clips=()
for spec in "90 1.0 120" "120 1.1 115" "150 0.95 125"; do
  read -r frames cycle speed <<<"$spec"
  clip="$dir/clips/walk_${frames}_${cycle}.bvh"
  "$python" "$root/tests/deploy/synthetic_walk.py" bvh "$clip" --frames "$frames" --cycle "$cycle" --speed "$speed"
  clips+=("$clip")
done
timeout 120 "$mocapd" import --store "$store" --tenant acme --database walks --quiet "${clips[@]}" >/dev/null ||
  fail "mocapd import failed"
"$python" "$root/tests/deploy/synthetic_walk.py" csv "$dir/wrists.csv" --frames 75 --cycle 1.02 --speed 118 --start 0.3

# 3. One server; the C++ SDK's reconstruction of the CSV (fixed lag, diagnostics).
start_mocapd "$mocapd" "$store" server
lag=4 k1=60 k2=40
timeout 120 "$mocap" --address "$server_address" --key "$key" reconstruct --database walks --csv "$dir/wrists.csv" \
  --lag $lag --k1 $k1 --k2 $k2 --diagnostics --quiet --json -o "$dir/cxx" >"$dir/cxx.summary.json" ||
  fail "mocap reconstruct failed"

# 4. The Python client on the same input, compared.
timeout 300 "$python" "$here/python_reconstruct_test.py" --stubs "$stubs" --address "$server_address" --key "$key" \
  --database walks --csv "$dir/wrists.csv" --cxx-json "$dir/cxx.json" --lag $lag --k1 $k1 --k2 $k2 \
  --sessions-before 1

# 5. PoseSearch: the C++ SDK's `mocap similar` on another walk, then Python's, compared.
"$python" "$root/tests/deploy/synthetic_walk.py" bvh "$dir/query.bvh" --frames 80 --cycle 1.05 --speed 117
timeout 300 "$mocap" --address "$server_address" --key "$key" similar --database walks --query "$dir/query.bvh" \
  --frames 5:70 --step 5 --top 5 --json >"$dir/similar.json" || fail "mocap similar failed"
timeout 300 "$python" "$here/python_pose_search_test.py" --stubs "$stubs" --address "$server_address" --key "$key" \
  --database walks --query "$dir/query.bvh" --frames 5:70 --step 5 --top 5 --cxx-json "$dir/similar.json"

#!/usr/bin/env bash
# The Python client (client/python, package mocap_client) against the C++ SDK: the Reconstruction
# and PoseSearch services from Python's grpcio (python_reconstruct_test.py,
# python_pose_search_test.py) and the package's example, client/python/examples/stream_csv.py.
#   usage: python_reconstruct_test.sh MOCAPD MOCAP PACKAGE_DIR|none
# PACKAGE_DIR is the build's Python client (BUILD/client/python: the package with the modules
# protoc and grpc_python_plugin generated from proto/mocap/v1/*.proto), or `none` when the build
# made none. Installs it with pip (offline, --no-deps --no-build-isolation) into a fresh venv made with
# --system-site-packages (Debian's python3-grpcio and python3-protobuf are the runtime); starts one
# `mocapd serve` on 127.0.0.1 over a store of synthetic walks; reconstructs a wrist CSV with
# `mocap reconstruct --csv ... --json` (C++ SDK); then runs the Python checks on the same CSV and
# config and compares; runs the example on the CSV and compares what it wrote with the C++ SDK's
# JSON, and runs it once more over TLS (a second server, a certificate made here); then searches similar poses of another walk with `mocap similar --json` (C++ SDK) and from
# Python, and compares. Skips (exit code 77) without a python3 that has grpc and google.protobuf
# (Debian: python3-grpcio, python3-protobuf), without venv and pip (python3-venv, python3-pip), or
# when the build made no Python client.
set -euo pipefail
usage="usage: python_reconstruct_test.sh MOCAPD MOCAP PACKAGE_DIR|none"
mocapd=${1:?$usage}
mocap=${2:?$usage}
package=${3:?$usage}
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
# shellcheck source=tests/deploy/test_lib.sh
source "$root/tests/deploy/test_lib.sh"

python=$(python_with grpc google.protobuf) ||
  skip "no python3 with grpc and google.protobuf (apt-get install python3-grpcio python3-protobuf)"
[ -x "$mocapd" ] || fail "no mocapd at $mocapd"
[ -x "$mocap" ] || fail "no mocap at $mocap"
[ "$package" != none ] ||
  skip "the build made no Python client: configure found no protoc with grpc_python_plugin (apt-get install protobuf-compiler protobuf-compiler-grpc, then configure again)"
if [ ! -f "$package/pyproject.toml" ] || [ ! -f "$package/mocap_client/v1/reconstruction_pb2_grpc.py" ]; then
  fail "no Python client in $package: build it first (cmake --build BUILD --target mocap_python_client)"
fi

test_lib_init python-interop
dir=$test_lib_dir

# 1. The package, installed as a user would into a fresh venv. A copy of it (pyproject.toml and
# mocap_client/ only) is installed, since pip builds in the folder it installs and the build dir
# may be shared by concurrent runs. Without pip in the venv the system's (python3-pip) is used
# through --system-site-packages; a venv with its own pip (python3-venv's ensurepip) otherwise.
venv=$dir/venv
"$python" -m venv --system-site-packages --without-pip "$venv" >"$dir/venv.log" 2>&1 ||
  skip "$python -m venv does not work (apt-get install python3-venv): $(tail -n 1 "$dir/venv.log")"
vpython=$venv/bin/python
if ! "$vpython" -m pip --version >/dev/null 2>&1; then
  rm -rf "$venv"
  "$python" -m venv --system-site-packages "$venv" >"$dir/venv.log" 2>&1 ||
    skip "no pip for a venv (apt-get install python3-pip python3-venv): $(tail -n 1 "$dir/venv.log")"
fi
mkdir -p "$dir/package"
cp -r "$package/pyproject.toml" "$package/mocap_client" "$dir/package/"
PIP_NO_INDEX=1 PIP_DISABLE_PIP_VERSION_CHECK=1 "$vpython" -m pip install --no-deps --no-build-isolation \
  "$dir/package" >"$dir/pip.log" 2>&1 || { tail -n 20 "$dir/pip.log"; fail "pip could not install the Python client"; }
installed=$(cd "$dir" && "$vpython" -c 'import mocap_client, mocap_client.v1.reconstruction_pb2_grpc; print(mocap_client.__file__, mocap_client.__version__)') ||
  fail "the installed package does not import (protobuf runtime $("$python" -c 'import google.protobuf as p; print(p.__version__)'))"
[[ $installed == "$venv"/* ]] || fail "mocap_client was imported from ${installed% *}, not from the venv"
note "python $python (grpcio $("$python" -c 'import grpc; print(grpc.__version__)')); mocap_client ${installed#* } installed in $venv"

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

# 3. One server; the C++ SDK's reconstructions of the CSV: one with overrides and diagnostics (for
# the protocol checks), one as the example asks (a fixed lag of 5, the defaults otherwise).
start_mocapd "$mocapd" "$store" server
lag=4 k1=60 k2=40
timeout 120 "$mocap" --address "$server_address" --key "$key" reconstruct --database walks --csv "$dir/wrists.csv" \
  --lag $lag --k1 $k1 --k2 $k2 --diagnostics --quiet --json -o "$dir/cxx" >"$dir/cxx.summary.json" ||
  fail "mocap reconstruct failed"
timeout 120 "$mocap" --address "$server_address" --key "$key" reconstruct --database walks --csv "$dir/wrists.csv" \
  --lag 5 --quiet --json -o "$dir/cxx_lag5" >"$dir/cxx_lag5.summary.json" || fail "mocap reconstruct --lag 5 failed"

# 4. The example, run as a user would (the installed package; the key from the environment).
(cd "$dir" && MOCAP_API_KEY=$key timeout 120 "$vpython" "$root/client/python/examples/stream_csv.py" \
  --address "$server_address" --database walks --csv "$dir/wrists.csv" --lag 5 -o "$dir/example.json" >"$dir/example.log" 2>&1) ||
  { tail -n 20 "$dir/example.log"; fail "examples/stream_csv.py failed"; }
note "stream_csv.py: $(tail -n 1 "$dir/example.log")"

# 5. The Python checks on the same input (the installed package's Client and stubs), compared.
timeout 300 "$vpython" "$here/python_reconstruct_test.py" --address "$server_address" --key "$key" \
  --database walks --csv "$dir/wrists.csv" --cxx-json "$dir/cxx.json" --lag $lag --k1 $k1 --k2 $k2 \
  --example-json "$dir/example.json" --example-cxx-json "$dir/cxx_lag5.json" --sessions-before 3

# 6. TLS as the C++ SDK does it: the example against a second server serving a certificate made
# here, trusting it with --tls-root-certs (without openssl to make one, not checked).
if command -v openssl >/dev/null; then
  openssl req -x509 -newkey rsa:2048 -nodes -days 1 -subj /CN=localhost \
    -addext subjectAltName=IP:127.0.0.1,DNS:localhost -keyout "$dir/tls.key" -out "$dir/tls.pem" \
    >"$dir/openssl.log" 2>&1 || fail "openssl could not make a test certificate"
  plain_address=$server_address
  start_mocapd "$mocapd" "$store" tls_server --tls-cert "$dir/tls.pem" --tls-key "$dir/tls.key"
  tls_address=$server_address server_address=$plain_address
  MOCAP_API_KEY=$key timeout 120 "$vpython" "$root/client/python/examples/stream_csv.py" \
    --address "$tls_address" --tls-root-certs "$dir/tls.pem" --database walks --csv "$dir/wrists.csv" \
    -o "$dir/example_tls.json" >"$dir/example_tls.log" 2>&1 ||
    { tail -n 20 "$dir/example_tls.log"; fail "examples/stream_csv.py --tls-root-certs failed"; }
  note "stream_csv.py over TLS: $(tail -n 1 "$dir/example_tls.log")"
else
  note "no openssl: TLS not checked"
fi

# 7. PoseSearch: the C++ SDK's `mocap similar` on another walk, then Python's, compared.
"$python" "$root/tests/deploy/synthetic_walk.py" bvh "$dir/query.bvh" --frames 80 --cycle 1.05 --speed 117
timeout 300 "$mocap" --address "$server_address" --key "$key" similar --database walks --query "$dir/query.bvh" \
  --frames 5:70 --step 5 --top 5 --json >"$dir/similar.json" || fail "mocap similar failed"
timeout 300 "$vpython" "$here/python_pose_search_test.py" --address "$server_address" --key "$key" \
  --database walks --query "$dir/query.bvh" --frames 5:70 --step 5 --top 5 --cxx-json "$dir/similar.json"

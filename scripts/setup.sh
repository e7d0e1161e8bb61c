#!/usr/bin/env bash
# One setup step for every place that builds the project: README quick start, CI and docker/Dockerfile.
# Installs the Debian packages (when missing; chromium for the viewer's page test, blender for
# the retargeted BVH's import test), then configures
# and builds with CMake + Ninja + ccache (the build runs `npm ci` in viewer/: the npm registry).
# Idempotent: a second run only checks packages and lets Ninja rebuild what changed.
#   usage: scripts/setup.sh [--no-build] [--with-clang] [--build-dir DIR] [--build-type TYPE] [--target T]...
#                           [-- extra cmake args]
#   --with-clang: also clang and its sanitizer and libFuzzer runtimes (the TSan build and the fuzz targets).
#   Builds are unity builds (CMake batches of 8 sources: a cold build in a third of the time);
#   pass -- -DCMAKE_UNITY_BUILD=OFF for one object per source.
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
build_dir="$repo/build"
build_type=RelWithDebInfo
do_build=1
with_clang=0
extra=()
targets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --no-build) do_build=0 ;;
    --with-clang) with_clang=1 ;;
    --build-dir) build_dir=$2; shift ;;
    --build-type) build_type=$2; shift ;;
    --target) targets+=(--target "$2"); shift ;;
    --) shift; extra=("$@"); break ;;
    *) echo "setup.sh: unknown option $1" >&2; exit 2 ;;
  esac
  shift
done

packages=(build-essential cmake ninja-build ccache pkg-config git xz-utils
  libgrpc++-dev protobuf-compiler-grpc libprotobuf-dev protobuf-compiler
  libsqlite3-dev libsqlitecpp-dev libeigen3-dev libflann-dev liblz4-dev liblapacke-dev libspdlog-dev libcpp-httplib-dev
  libgtest-dev libgmock-dev libbenchmark-dev libcli11-dev nlohmann-json3-dev libxxhash-dev libssl-dev clang-format
  nginx python3-grpcio python3-protobuf python3-venv python3-pip python3-yaml chromium blender)
# The viewer's script (viewer/, compiled into mocap and mocap-eval) is built with npm: Debian's
# Node.js where the machine has none (one installed otherwise, with its own npm, is kept).
command -v npm >/dev/null 2>&1 || packages+=(nodejs npm)
[ $with_clang -eq 0 ] || packages+=(clang)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup.sh: installing ${missing[*]}"
  sudo_cmd=(); [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -q
  "${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
fi
# clang's sanitizer and libFuzzer runtimes are in libclang-rt-N-dev, which clang only recommends.
if [ $with_clang -eq 1 ] && ! clang++ -print-file-name=libclang_rt.fuzzer-x86_64.a | grep -q /; then
  sudo_cmd=(); [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends \
    "libclang-rt-$(clang++ -dumpversion | cut -d. -f1)-dev"
fi

[ $do_build -eq 1 ] || exit 0
jobs=$(nproc)
cmake -S "$repo" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE="$build_type" \
  -DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_UNITY_BUILD=ON -DCMAKE_UNITY_BUILD_BATCH_SIZE=8 "${extra[@]}" >/dev/null
cmake --build "$build_dir" -j "$jobs" "${targets[@]}"

#!/usr/bin/env bash
# The SDK builds on its own (issue #27 item 5): configures this repository with
# -DMOCAP_SDK_ONLY=ON in a fresh tree (no server, tools, viewer, Node.js or npm: the configure
# must not look for them), builds and installs mocap_client, then builds the SDK's examples as a
# separate project against the installed package with find_package(mocap_client), as a user would.
#   usage: sdk_only_install_test.sh SOURCE_DIR WORK_DIR
set -euo pipefail
source_dir=$(cd "${1:?usage: sdk_only_install_test.sh SOURCE_DIR WORK_DIR}" && pwd)
work=${2:?usage: sdk_only_install_test.sh SOURCE_DIR WORK_DIR}
rm -rf "$work" && mkdir -p "$work"
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
start=$(date +%s)
cmake -S "$source_dir" -B "$work/build" -G Ninja -DMOCAP_SDK_ONLY=ON -DCMAKE_INSTALL_PREFIX="$work/prefix" \
  "${launcher[@]}" >"$work/configure.log"
if grep -q -i -E '^(MOCAP_NODE|MOCAP_NPM|SQLite3_INCLUDE_DIR|flann_DIR|Eigen3_DIR):' "$work/build/CMakeCache.txt"; then
  echo "FAIL: the SDK-only configure looked for what only the server or the tools need:"
  grep -i -E '^(MOCAP_NODE|MOCAP_NPM|SQLite3_INCLUDE_DIR|flann_DIR|Eigen3_DIR):' "$work/build/CMakeCache.txt"
  exit 1
fi
cmake --build "$work/build" -j "$(nproc)" >"$work/build.log" || { tail -n 30 "$work/build.log"; exit 1; }
cmake --install "$work/build" >"$work/install.log"
for installed in include/mocap/client.h include/mocap/v1/reconstruction.pb.h lib/libmocap_client.a \
  lib/cmake/mocap_client/mocap_clientConfig.cmake; do
  [ -f "$work/prefix/$installed" ] || { echo "FAIL: $installed was not installed"; exit 1; }
done
sdk_seconds=$(($(date +%s) - start))
cmake -S "$source_dir/tests/sdk/consumer" -B "$work/consumer" -G Ninja -DCMAKE_PREFIX_PATH="$work/prefix" \
  -DMOCAP_EXAMPLES_DIR="$source_dir/client/examples" >"$work/consumer.log"
cmake --build "$work/consumer" -j "$(nproc)" >>"$work/consumer.log" || { tail -n 30 "$work/consumer.log"; exit 1; }
[ -x "$work/consumer/stream_wrists" ] && [ -x "$work/consumer/list_and_import" ] ||
  { echo "FAIL: the consumer's examples were not built"; exit 1; }
echo "the SDK alone configured, built and installed in ${sdk_seconds} s; the examples built against it with find_package(mocap_client)"

#!/usr/bin/env bash
# The README's test command: sets up everything (packages, build) and runs the whole test suite.
# Tests that need ../shared/data unpack it on first use (into ~/.cache/mocap/data) or skip with a
# message when it is absent.
#   usage: scripts/test.sh [--sanitize | --tsan] [extra ctest arguments]
#   --sanitize: a second build in build-asan with AddressSanitizer + UndefinedBehaviorSanitizer,
#               by clang at -O1 with line tables only, as the TSan build: gcc at -O2 with full debug
#               information took 37 min of a cold CI machine's 2 cores to build it, clang 14 min
#               (also skips mocap-eval --quick, minutes under the sanitizers; its code is unit-tested)
#               (skips the every-file landmark sweep, which the plain run covers, the Docker
#               runtime check, which sanitizer runtimes would fail, the browser page test, whose
#               C++ side mocap_html_view_tests covers and whose report step runs mocap-eval, and the
#               SDK-only install, which configures and builds a tree of its own without sanitizers).
#   --tsan: a ThreadSanitizer build in build-tsan of the suites where threads meet (storage, server,
#           client, regressions; the mocapd they start is instrumented too). Every report, from a
#           test or from a server it started, is written under build-tsan/tsan-reports and fails
#           the run; tests/tsan.supp lists what is suppressed and why.
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
if [ "${1:-}" = "--tsan" ]; then
  shift
  "$repo/scripts/setup.sh" --with-clang --build-dir "$repo/build-tsan" --build-type Tsan --target mocap_concurrency_tests -- \
    -DCMAKE_CXX_COMPILER=clang++ -DMOCAP_TSAN=ON -DMOCAP_BUILD_BENCHMARKS=OFF -DCMAKE_CXX_FLAGS_TSAN="-O1 -gline-tables-only"
  cd "$repo/build-tsan"
  reports="$repo/build-tsan/tsan-reports"
  rm -rf "$reports" && mkdir -p "$reports"
  export TSAN_OPTIONS="log_path=$reports/report second_deadlock_stack=1 suppressions=$repo/tests/tsan.supp"
  status=0
  # (The every-file landmark sweep and export round trip are single-threaded parsing and writing,
  # minutes under TSan: the plain run has them.)
  ctest --output-on-failure -j "$(nproc)" -E 'InspectSharedDataTest|EveryFileOfEverySharedSet' "$@" || status=$?
  if compgen -G "$reports/report.*" >/dev/null; then
    echo "ThreadSanitizer reports ($(ls "$reports" | wc -l) processes):"
    cat "$reports"/report.*
    status=1
  fi
  exit $status
fi
if [ "${1:-}" = "--sanitize" ]; then
  shift
  "$repo/scripts/setup.sh" --with-clang --build-dir "$repo/build-asan" --build-type Asan -- \
    -DCMAKE_CXX_COMPILER=clang++ -DMOCAP_SANITIZE=ON -DMOCAP_BUILD_BENCHMARKS=OFF \
    -DCMAKE_CXX_FLAGS_ASAN="-O1 -gline-tables-only -DNDEBUG"
  cd "$repo/build-asan"
  export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
  ctest --output-on-failure -j "$(nproc)" -E 'docker_runtime_packages|InspectSharedDataTest|EveryFileOfEverySharedSet|mocap_eval_quick|viewer_page|sdk_only_install' "$@"
  exit
fi
"$repo/scripts/setup.sh"
# Unpack the shared data once, before tests run in parallel (they also do it on demand, locked).
if [ -x "$repo/../shared/data/unpack.sh" ]; then
  "$repo/../shared/data/unpack.sh" "${MOCAP_DATA_CACHE_DIR:-$HOME/.cache/mocap/data}" >/dev/null
fi
cd "$repo/build"
ctest --output-on-failure -j "$(nproc)" "$@"

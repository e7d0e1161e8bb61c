#!/usr/bin/env bash
# Every program the README, the guides in docs/, the SDK's and viewer's READMEs, the scripts and
# the benchmark scripts run from the build tree (build/DIR/mocap...) is one the build makes: a moved
# binary otherwise breaks a documented command without any test noticing (it did once: mocapd moved
# from server/ to mocapd/).
#   usage: tests/check_script_paths.sh SOURCE_DIR BUILD_DIR
set -euo pipefail
source_dir=$1
build_dir=$2
cd "$source_dir"
status=0
checked=0
while IFS=: read -r file path; do
  checked=$((checked + 1))
  if [ ! -x "$build_dir/${path#build/}" ]; then
    echo "$file names $path, which the build does not make"
    status=1
  fi
done < <(grep -o -E 'build/[a-z_-]+/mocap[a-z_-]*' README.md docs/*.md docs/*/*.md client/README.md viewer/README.md \
  scripts/*.sh benchmarks/*.sh docker/* .ci/run 2>/dev/null |
  sort -u)
echo "checked $checked program paths"
[ "$checked" -gt 0 ] || { echo "no program paths found: the pattern is stale"; exit 1; }
exit $status

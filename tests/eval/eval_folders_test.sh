#!/usr/bin/env bash
# mocap-eval run the way a user runs it on folders of their own (issue #10: it reconstructed, then
# aborted on a JSON type error before writing any report): a database folder and a test folder of
# Bandai clips (symlinks into the unpacked shared data), then the report must exist and name both.
#   usage: eval_folders_test.sh MOCAP_EVAL DATA_CACHE_DIR SHARED_DATA_DIR
set -euo pipefail
eval_bin=$1 cache=$2 shared=$3
if [ ! -x "$shared/unpack.sh" ]; then echo "SKIP: no shared data at $shared"; exit 77; fi
"$shared/unpack.sh" "$cache" bandai-namco-2 >/dev/null
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
mkdir -p "$work/my database" "$work/my tests"
ls "$cache/bandai-namco-2"/dataset-2_walk_*_00[0-2].bvh | head -12 | while read -r f; do ln -s "$f" "$work/my database/"; done
ls "$cache/bandai-namco-2"/dataset-2_walk_*_005.bvh | head -2 | while read -r f; do ln -s "$f" "$work/my tests/"; done
"$eval_bin" --database-dir "$work/my database" --test "$work/my tests" --max-frames 40 --k1 200 --k2 50 --threads 1 \
  --out "$work/out" >"$work/log" 2>&1 || { cat "$work/log"; echo "FAIL: mocap-eval exited $?"; exit 1; }
for f in report.json report.md plots/error_by_content.svg bvh; do
  [ -e "$work/out/$f" ] || { cat "$work/log"; echo "FAIL: no $f"; exit 1; }
done
grep -q "my database" "$work/out/report.json" || { echo "FAIL: report.json does not name the database folder"; exit 1; }
grep -q "nearest_average" "$work/out/report.json" || { echo "FAIL: no average-of-10 baseline"; exit 1; }
# Test clips on another rig (issue #22): scored on body landmarks at their own rate and unit.
"$shared/unpack.sh" "$cache" other-rigs >/dev/null
mkdir -p "$work/their rig"
ln -s "$cache/other-rigs/mixamo_test_freebvh.bvh" "$cache/other-rigs/xia_dme_neutral_01_000.bvh" "$work/their rig/"
"$eval_bin" --database-dir "$work/my database" --test "$work/their rig" --max-frames 60 --k1 200 --k2 50 --threads 1 \
  --out "$work/out-rigs" >"$work/log" 2>&1 || { cat "$work/log"; echo "FAIL: mocap-eval on another rig exited $?"; exit 1; }
[ -e "$work/out-rigs/landmarks.json" ] || { cat "$work/log"; echo "FAIL: no landmarks.json"; exit 1; }
grep -q '"xia_dme_neutral_01_000.bvh"' "$work/out-rigs/landmarks.json" || { echo "FAIL: clip not scored"; exit 1; }
grep -q "^| named | 2 |" "$work/out-rigs/landmarks.md" || { cat "$work/out-rigs/landmarks.md"; echo "FAIL: no row"; exit 1; }
echo "ok: report written for folders given on the command line, and for clips on other rigs"

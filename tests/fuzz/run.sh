#!/usr/bin/env bash
# Fuzzing (issue #14): builds the libFuzzer targets with clang (build-fuzz: every library with
# ASan + UBSan + fuzzer instrumentation) and runs each for SECONDS, from seed corpora made of real
# files (BVH clips of ../shared/data cut to 40 frames; the wrist CSV, pose JSON and session request
# seeds of tests/fuzz/seeds, the last encoded with protoc; target rigs and pose search requests made
# from those clips and poses by make_proto_seeds.py). Exits non-zero on any crash, leak or timeout;
# the reproducer is left in build-fuzz/findings/TARGET/.
#   usage: tests/fuzz/run.sh [SECONDS (60)] [TARGET...]   (CI: 40 s per target; long run: 600)
set -euo pipefail
repo=$(cd "$(dirname "$0")/../.." && pwd)
seconds=${1:-60}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(bvh_reader_fuzz wrist_csv_fuzz session_request_fuzz pose_query_json_fuzz target_rig_fuzz
  pose_search_request_fuzz)
build="$repo/build-fuzz"

"$repo/scripts/setup.sh" --no-build --with-clang

# -O1 and line tables only: what fuzzing wants, and half the compile time of -O2 -g.
cmake -S "$repo" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Fuzz -DCMAKE_CXX_FLAGS_FUZZ="-O1 -gline-tables-only" \
  -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_UNITY_BUILD=ON -DCMAKE_UNITY_BUILD_BATCH_SIZE=8 \
  -DMOCAP_FUZZ=ON -DMOCAP_BUILD_TESTS=OFF \
  -DMOCAP_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build "$build" -j "$(nproc)" --target mocap_fuzzers

# Seed corpora (rebuilt each run; what the fuzzer adds stays in build-fuzz/corpus/TARGET).
seeds="$build/seeds"
rm -rf "$seeds" && mkdir -p "$seeds"/{bvh_reader_fuzz,wrist_csv_fuzz,session_request_fuzz,pose_query_json_fuzz,target_rig_fuzz,pose_search_request_fuzz}
data="${MOCAP_DATA_CACHE_DIR:-$HOME/.cache/mocap/data}"
if [ -x "$repo/../shared/data/unpack.sh" ]; then "$repo/../shared/data/unpack.sh" "$data" >/dev/null; fi
python3 - "$data" "$seeds/bvh_reader_fuzz" <<'PY'
# One clip per data set and content type, its hierarchy and first 40 frames (Frames: fixed up).
import pathlib, re, sys
data, out = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
seen, sets = set(), set()
for path in sorted(data.glob("*/*.bvh")):
    kind = (path.parent.name, re.sub(r"[_-]?\d+$", "", path.stem))
    # Up to 40 kinds, and the first clip of every data set (each rig is a target rig seed).
    if kind in seen or (len(seen) >= 40 and path.parent.name in sets):
        continue
    seen.add(kind)
    sets.add(path.parent.name)
    text = path.read_text(errors="replace").splitlines()
    m = next(i for i, line in enumerate(text) if line.strip().startswith("Frame Time"))
    frames = text[m + 1:m + 41]
    head = [("Frames: %d" % len(frames)) if l.strip().startswith("Frames:") else l for l in text[:m + 1]]
    (out / f"{path.parent.name}_{path.stem}.bvh").write_text("\n".join(head + frames) + "\n")
PY
cp "$repo"/tests/testdata/bvh/valid/*.bvh.txt "$repo"/tests/testdata/bvh/malformed/*.bvh.txt "$seeds/bvh_reader_fuzz/"
cp "$repo"/tests/fuzz/seeds/csv/*.csv "$seeds/wrist_csv_fuzz/"
cp "$repo"/tests/fuzz/seeds/pose/*.json "$seeds/pose_query_json_fuzz/"
for seed in "$repo"/tests/fuzz/seeds/session/*.txtpb; do
  protoc --encode=mocap.v1.ReconstructTrajectoryRequest -I "$repo/proto" "$repo/proto/mocap/v1/reconstruction.proto" \
    <"$seed" >"$seeds/session_request_fuzz/$(basename "$seed" .txtpb).bin"
done
# Target rigs (both forms) and pose search requests from the first real clip of each data set and
# the pose files (tests/fuzz/make_proto_seeds.py), plus one small non-human test BVH.
rig_clips=()
for dir in "$data"/*/; do
  first=$(ls "$seeds/bvh_reader_fuzz/$(basename "$dir")"_*.bvh 2>/dev/null | head -1 || true)
  [ -n "$first" ] && rig_clips+=("$first")
done
python3 "$repo/tests/fuzz/make_proto_seeds.py" "$build/proto-seeds" "${rig_clips[@]}" "$repo"/tests/testdata/bvh/valid/order_xyz.bvh.txt \
  -- "$repo"/tests/fuzz/seeds/pose/*.json
for seed in "$build"/proto-seeds/target_rig_fuzz/*.txtpb; do
  protoc --encode=mocap.v1.TargetRig -I "$repo/proto" "$repo/proto/mocap/v1/target_rig.proto" \
    <"$seed" >"$seeds/target_rig_fuzz/$(basename "$seed" .txtpb).bin"
done
for seed in "$build"/proto-seeds/pose_search_request_fuzz/*.txtpb; do
  protoc --encode=mocap.v1.FindSimilarPosesRequest -I "$repo/proto" "$repo/proto/mocap/v1/pose_search.proto" \
    <"$seed" >"$seeds/pose_search_request_fuzz/$(basename "$seed" .txtpb).bin"
done
rm -rf "$build/proto-seeds"

export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
status=0
for target in "${targets[@]}"; do
  corpus="$build/corpus/$target" findings="$build/findings/$target"
  mkdir -p "$corpus" "$findings"
  log="$build/$target.log"
  if "$build/tests/fuzz/$target" "$corpus" "$seeds/$target" -max_total_time="$seconds" -timeout=20 \
      -rss_limit_mb=2560 -max_len=65536 -print_final_stats=1 -artifact_prefix="$findings/" >"$log" 2>&1; then
    verdict="no crash, leak or timeout"
  else
    verdict="FAILED (see $log; reproducer in $findings/)"
    status=1
  fi
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  echo "fuzz $target: ${seconds} s, ${runs:-?} inputs (${rate:-?}/s), corpus $(ls "$corpus" | wc -l) files: $verdict"
done
exit $status

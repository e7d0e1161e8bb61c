#!/usr/bin/env bash
# The README's main command: sets up everything, imports motion into a SQLite motion store, starts
# the server on that store, streams held-out wrist trajectories to it through the client SDK
# (`mocap reconstruct`) and writes the reconstructed whole-body motion (BVH + JSON + summary in
# out/stream/, played in a browser by out/view.html), plus the offline evaluation (report.html,
# report.md and plots in out/reconstruction/).
#   usage: scripts/quickstart.sh [BVH_FILE_OR_FOLDER...]
# Without arguments it imports the shared data sets (../shared/data) when present.
# Output: var/mocap.db (the store) and out/.
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
"$repo/scripts/setup.sh"
mocapd="$repo/build/mocapd/mocapd"
mocap="$repo/build/client/mocap"
store="$repo/var/mocap.db"
out="$repo/out"
mkdir -p "$out" "$out/stream"

# shellcheck source=scripts/temporary_server.sh
source "$repo/scripts/temporary_server.sh"
trap stop_temporary_server EXIT

# The server on the store (a free loopback port, a fresh key revoked at the end).
start_server() {
  start_temporary_server "$mocapd" "$store" "$out/stream/server.log"
  echo "== mocapd serve listening on $address (log: $out/stream/server.log)"
}

# Streams the wrists of each BVH clip (forward kinematics + 0.5 cm noise) through the server with
# a fixed lag of 5 frames, as a live tracker would, and writes out/stream/NAME.{bvh,json}.
stream_clips() {
  local database=$1; shift
  : > "$out/stream/summary.txt"
  for clip in "$@"; do
    name=$(basename "$clip" .bvh)
    echo "-- $name" | tee -a "$out/stream/summary.txt"
    "$mocap" --address "$address" reconstruct --database "$database" --bvh "$clip" --noise-cm 0.5 --seed 1 \
      --lag 5 --quiet -o "$out/stream/$name" | tee -a "$out/stream/summary.txt"
  done
}

# One page playing every streamed reconstruction side by side, with its wrist inputs and estimated
# ankles as traces (from NAME.json beside NAME.bvh): out/view.html, opened by any browser.
view_streamed() {
  "$mocap" view "$out"/stream/*.bvh --layout side-by-side --follow --title "mocap quick start: streamed reconstructions" \
    -o "$out/view.html"
}

inputs=("$@")
database=motion
if [ ${#inputs[@]} -eq 0 ]; then
  shared="$repo/../shared/data"
  if [ ! -x "$shared/unpack.sh" ]; then
    echo "quickstart: no BVH inputs given and no ../shared/data beside the repository." >&2
    echo "usage: scripts/quickstart.sh FOLDER_OF_BVH_FILES..." >&2
    exit 2
  fi
  data="${MOCAP_DATA_CACHE_DIR:-$HOME/.cache/mocap/data}"
  "$shared/unpack.sh" "$data" bandai-namco-2 bandai-namco-1 cmu-cc
  # One database per rig: the two Bandai sets share a rig, cmu-cc has its own.
  # bandai-namco-2 as the standard split's database (takes not ≡ 3 mod 10); the held-out takes
  # (≡ 3 mod 10) are what the server reconstructs below.
  find "$data/bandai-namco-2" -name '*.bvh' ! -name '*3.bvh' -print0 | sort -z \
    | xargs -0 "$mocapd" import --store "$store" --database bandai-namco-2
  "$mocapd" import --store "$store" --database bandai-namco-1 "$data/bandai-namco-1"
  # cmu-cc comes on two rigs (41 files rooted at the hips, 4 under an extra Z-up root node): the
  # database takes the first rig and --keep-going reports the files on the other one.
  "$mocapd" import --store "$store" --database cmu-cc --keep-going "$data/cmu-cc"
  sample_bandai="$data/bandai-namco-2/dataset-2_walk_normal_001.bvh"
  sample_cmu="$data/cmu-cc/002_01.bvh"
  "$mocapd" inspect --json "$sample_bandai" "$sample_cmu" > "$out/inspect.json"
  # Cross-skeleton search: a CMU walk (101 joints, Z-up root, 60 fps) against the Bandai rig.
  "$mocapd" similar --store "$store" --database bandai-namco-2 --query "$sample_cmu" \
    --frames 30:150 --step 30 --top 5 --suppress 15 --json > "$out/similar.json"
  # Whole-body reconstruction through the server: held-out clips of the standard split streamed
  # as live wrist samples.
  echo
  start_server
  echo "== Streaming held-out clips' wrists to the server (mocap reconstruct --lag 5)"
  stream_clips bandai-namco-2 "$data"/bandai-namco-2/dataset-2_{walk,run,wave-both-hands}_normal_003.bvh
  view_streamed
  # The same engine offline on a subset of the standard split, measured against the captured motion.
  echo
  echo "== Evaluating held-out clips offline (mocap-eval --quick)"
  "$repo/build/eval/mocap-eval" --quick --out "$out/reconstruction"
  echo
  echo "== Poses of $(basename "$sample_cmu") (cmu-cc) matched in bandai-namco-2 (first matches)"
  "$mocapd" similar --store "$store" --database bandai-namco-2 --query "$sample_cmu" \
    --frames 60:120 --step 60 --top 3 --suppress 15
else
  "$mocapd" import --store "$store" --database "$database" "${inputs[@]}"
  first=$(find "${inputs[@]}" -iname '*.bvh' -type f -print -quit)
  "$mocapd" inspect --json "$first" > "$out/inspect.json"
  # Reconstruct the first clip from its own wrists against the whole folder (a demonstration: the
  # clip is in the database; mocap-eval --test with held-out files measures for real).
  start_server
  stream_clips "$database" "$first"
  view_streamed
  "$repo/build/eval/mocap-eval" --database-dir "${inputs[@]}" --test "$first" --out "$out/reconstruction"
fi
echo
echo "== Motion databases in $store"
"$mocapd" databases --store "$store"
"$mocapd" databases --store "$store" --json > "$out/databases.json"
echo
echo "Wrote $out/: view.html (open it in a browser: the streamed reconstructions played side by side, with"
echo "  their wrist inputs and estimated ankles as traces), databases.json, inspect.json (groups, landmarks,"
echo "  up axis, units of sample files)$([ -f "$out/similar.json" ] && echo ', similar.json'),"
echo "  stream/ (*.bvh: motion reconstructed by the server from streamed wrists; *.json: every frame, the"
echo "  session's skeleton and summary; summary.txt),"
echo "  reconstruction/ (offline evaluation: report.html with an embedded player, report.md, plots/*.svg, bvh/)."

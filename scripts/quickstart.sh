#!/usr/bin/env bash
# The README's main command: sets up everything, imports motion into a SQLite motion store, shows
# what is in it, and reconstructs whole-body motion from wrists (BVH + report in out/reconstruction).
#   usage: scripts/quickstart.sh [BVH_FILE_OR_FOLDER...]
# Without arguments it imports the shared data sets (../shared/data) when present.
# Output: var/mocap.db (the store) and out/ (what the importer found, as JSON you can open).
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
"$repo/scripts/setup.sh"
mocapd="$repo/build/server/mocapd"
store="$repo/var/mocap.db"
out="$repo/out"
mkdir -p "$out"

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
  "$mocapd" import --store "$store" --database bandai-namco-2 "$data/bandai-namco-2"
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
  # Whole-body reconstruction from wrists: one held-out clip per content type of the standard
  # split (wrists by forward kinematics + 0.5 cm noise), written as BVH with a report.
  echo
  echo "== Reconstructing held-out clips from their wrists (mocap-eval --quick)"
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
  "$repo/build/eval/mocap-eval" --database-dir "${inputs[@]}" --test "$first" --out "$out/reconstruction"
fi
echo
echo "== Motion databases in $store"
"$mocapd" databases --store "$store"
"$mocapd" databases --store "$store" --json > "$out/databases.json"
echo
echo "Wrote $out/: databases.json, inspect.json (groups, landmarks, up axis, units of sample files)$([ -f "$out/similar.json" ] && echo ', similar.json'),"
echo "  reconstruction/ (report.md, plots/*.svg, bvh/*.bvh: reconstructed motions to open in Blender or any BVH viewer)."

#!/usr/bin/env bash
# How soon a long whole trajectory sized by its reach is answered (issue #24: its held samples were
# fed to the session in one task from the end of the input to the summary): a `mocapd serve
# --read-only` on the quick start's store, then one Reconstruct stream of SECONDS of a synthetic
# walk at 60 Hz (the wrists swinging at 0.9 Hz, 1.2 m/s) sent at once, `estimate_performer_height`
# and a whole-trajectory window, through the Python client. Prints the frames, the total time, when
# the first frames came and the largest gap between two frames replies (about one compute task).
#   usage: benchmarks/long_trajectory.sh [SECONDS]   (default 590: just under the 600 s hold limit)
#   env: STORE (var/mocap.db), PYTHON (/usr/bin/python3: Debian's, with python3-grpcio)
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
store=${STORE:-$repo/var/mocap.db}
python=${PYTHON:-/usr/bin/python3}
[ -f "$store" ] || { echo "no store at $store: run scripts/quickstart.sh first" >&2; exit 2; }
[ -d "$repo/build/client/python/mocap_client" ] || { echo "no Python client: build the project first" >&2; exit 2; }
# shellcheck source=scripts/temporary_server.sh
source "$repo/scripts/temporary_server.sh"
trap stop_temporary_server EXIT
start_temporary_server "$repo/build/mocapd/mocapd" "$store" "$repo/build/long_trajectory_server.log" --read-only

run() {
  ADDRESS=$address PYTHONPATH="$repo/build/client/python" "$python" - "$1" <<'PY'
import math, os, sys, time
import mocap_client
from mocap_client.v1 import reconstruction_pb2

def samples(seconds, rate=60.0):
    for i in range(int(seconds * rate)):
        t = i / rate
        swing = 0.15 * math.sin(2 * math.pi * 0.9 * t)
        bob = 0.85 + 0.02 * math.cos(4 * math.pi * 0.9 * t)
        s = reconstruction_pb2.WristSample(time=t)
        s.left.x, s.left.y, s.left.z = 1.2 * t + swing, bob, 0.22
        s.right.x, s.right.y, s.right.z = 1.2 * t - swing, bob, -0.22
        yield s

seconds = float(sys.argv[1])
config = reconstruction_pb2.SessionConfig(database="bandai-namco-2", estimate_performer_height=True,
                                          client_label="long_trajectory.sh")
config.sub_interval.window_frames = 0
frames, gaps, first, last = 0, [], None, None
with mocap_client.Client(os.environ["ADDRESS"], os.environ["MOCAP_API_KEY"]) as client:
    began = time.monotonic()
    for reply in client.reconstruct(config, samples(seconds), samples_per_message=600):
        if reply.WhichOneof("kind") != "frames":
            continue
        now = time.monotonic()
        first = now - began if first is None else first
        if last is not None:
            gaps.append(now - last)
        last, frames = now, frames + len(reply.frames.frames)
    total = time.monotonic() - began
print(f"{seconds:.0f} s of input: {frames} frames in {total:.1f} s; first frames after {first:.1f} s; "
      f"largest gap between frames replies {max(gaps, default=0.0):.2f} s")
PY
}
run 5 >/dev/null  # builds the database's indices first
run "${1:-590}"

"""ARKit, two phones held in the hands: per ARFrame, the camera's transform in the ARKit world,
logged as one JSON object per line (docs/devices/arkit.md), one log per phone (left then right) or
one log with a "hand" field in each record:

  {"time": 1700000000.123456, "tracking": "normal", "transform": [16 numbers, column-major]}

time in seconds on a clock both phones share (the frame's timestamp moved onto Unix time: each
phone's ARFrame.timestamp counts from its own boot), tracking the camera's trackingState (normal,
limited..., notAvailable), transform ARFrame.camera.transform (simd_float4x4, columns one after
another). ARKit's world: right-handed, Y up (gravity), metres, origin where the session started:
the floor is unknown (--floor calibrate, or the floor plane's y with --floor). Both phones must
share one world (an ARWorldMap both relocalised to): two sessions' worlds differ by where and
how each phone started.
"""

import math

from .frames import Convention, determinant, quat_from_matrix
from .logs import ConvertError, field, hand_name, number, read_json_lines
from .wrists import INFERRED, TRACKED, HandSample, frames_from_two_streams, require_increasing

NAME = "arkit"
SUMMARY = "ARKit ARFrame.camera.transform of two phones: JSON lines {time, tracking, transform[16]}, " \
          "one log per phone (left right) or one with a hand field"
CONVENTION = Convention(1.0, "+Y", "right")
HAS_ORIENTATION = True
DEFAULT_FLOOR = "calibrate"
MAX_INPUTS = 2
INPUTS_HELP = "one log with a \"hand\" field per record, or two logs: the left hand's phone, then the right's"
# Interpolating one phone's samples onto the other's times: no further apart than this (seconds).
MAX_GAP = 0.1


def _tracking(where, record):
    state = field(where, record, "tracking")
    if state == "normal":
        return TRACKED
    if isinstance(state, str) and state.startswith("limited"):
        return INFERRED
    if state == "notAvailable":
        return None
    raise where.error(f"unknown tracking state {state!r}: expected normal, limited or notAvailable")


def _pose(where, record):
    m = field(where, record, "transform")
    if not isinstance(m, list) or len(m) != 16:
        raise where.error("\"transform\" should be the 16 numbers of a simd_float4x4, column after column")
    m = [number(where, v, f"transform[{i}]") for i, v in enumerate(m)]
    if max(abs(m[3]), abs(m[7]), abs(m[11]), abs(m[15] - 1)) > 1e-4:
        raise where.error("the transform's last row is not 0 0 0 1: write the matrix column after column "
                          "(columns.0 ... columns.3), as simd_float4x4 stores it, not row after row")
    rotation = tuple(tuple(m[col * 4 + row] for col in range(3)) for row in range(3))
    gram = max(abs(sum(rotation[k][i] * rotation[k][j] for k in range(3)) - (i == j)) for i in range(3)
               for j in range(3))
    if gram > 1e-3 or determinant(rotation) < 0:
        raise where.error("the transform's upper 3x3 is not a rotation")
    return (m[12], m[13], m[14]), quat_from_matrix(rotation)


def _samples(where, record, hand_of_file, streams):
    if hand_of_file is None:
        hand = hand_name(where, field(where, record, "hand"))
    else:
        hand = hand_of_file
        if "hand" in record and hand_name(where, record["hand"]) != hand:
            raise where.error(f"a {record['hand']} record in the {hand} hand's log")
    time = number(where, field(where, record, "time"), "time")
    stream = streams[hand]
    require_increasing(where, time, stream[-1].time if stream else None, f"the {hand} phone's time")
    confidence = _tracking(where, record)
    if confidence is None:
        stream.append(HandSample.lost(time, where))
    else:
        position, orientation = _pose(where, record)
        stream.append(HandSample(time, position, orientation, confidence, where))


def read(paths, args):
    streams = {"left": [], "right": []}
    if len(paths) == 1:
        for where, record in read_json_lines(paths[0]):
            _samples(where, record, None, streams)
    else:
        for path, hand in zip(paths, ("left", "right")):
            for where, record in read_json_lines(path):
                _samples(where, record, hand, streams)
    logs = ", ".join(map(str, paths))
    for hand, stream in streams.items():
        if not stream:
            raise ConvertError(f"{logs}: no {hand} hand's samples")
    if math.fabs(streams["left"][0].time - streams["right"][0].time) > 60:
        raise ConvertError(f"{logs}: the two phones' samples start more than a minute apart: are both times on "
                           "one clock (Unix time, not each phone's own ARFrame.timestamp)?")
    return frames_from_two_streams(streams["left"], streams["right"], MAX_GAP)

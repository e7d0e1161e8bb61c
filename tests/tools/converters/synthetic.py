"""A known wrist trajectory in the server's frame, and the same motion written as each device's log.

The canonical motion (metres, right-handed, Y up, floor at y = 0): a person walking at 1.2 m/s
along a heading 30° off the axes, arms swinging, each hand turning about several axes. The logs
express it in each source's conventions with formulas written here from the platforms' own
documentation, independently of tools/converters: a converter that gets an axis, a sign, a unit,
a quaternion component or a matrix order wrong gives another trajectory back.
"""

import json
import math

RATE = 60.0
FRAMES = 120
HEADING = math.radians(30)
FORWARD = (math.sin(HEADING), 0.0, -math.cos(HEADING))  # walking direction
RIGHT = (math.cos(HEADING), 0.0, math.sin(HEADING))  # forward × up
UP = (0.0, 1.0, 0.0)
OMEGA = 2 * math.pi * 0.9  # arm swing, rad/s
SPEED = 1.2


# --- small vector and quaternion helpers (x, y, z, w), kept apart from the converter's ---

def add(*vs):
    return tuple(sum(c) for c in zip(*vs))


def scale(s, v):
    return tuple(s * c for c in v)


def qmul(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz)


def axis_angle(axis, angle):
    s = math.sin(angle / 2)
    return (axis[0] * s, axis[1] * s, axis[2] * s, math.cos(angle / 2))


def rotate(q, v):
    x, y, z, w = q
    p = qmul(qmul(q, (v[0], v[1], v[2], 0.0)), (-x, -y, -z, w))
    return p[:3]


def angle_between(a, b):
    """Degrees of the rotation from a to b (well conditioned near 0, unlike acos of the dot product)."""
    r = qmul((-a[0], -a[1], -a[2], a[3]), b)
    return math.degrees(2 * math.atan2(math.sqrt(r[0] ** 2 + r[1] ** 2 + r[2] ** 2), abs(r[3])))


def matvec(m, v):
    return tuple(sum(m[i][k] * v[k] for k in range(3)) for i in range(3))


def det(m):
    return (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
            m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))


def quat_to_matrix(q):
    x, y, z, w = q
    return ((1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)),
            (2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)),
            (2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)))


# --- the canonical motion ---

def times():
    return [i / RATE for i in range(FRAMES)]


def body(t):
    """The pelvis (hip centre) at time t."""
    return add(scale(SPEED * t, FORWARD), (0.0, 0.95 + 0.02 * math.cos(2 * OMEGA * t), 0.0))


def wrist(hand, t):
    side = -1.0 if hand == "left" else 1.0
    swing = -side * 0.25 * math.sin(OMEGA * t)  # the arms swing in opposition
    height = 0.85 + 0.03 * math.cos(2 * OMEGA * t + (0.0 if hand == "left" else 0.7))
    return add(scale(SPEED * t, FORWARD), scale(side * 0.2, RIGHT), scale(swing, FORWARD), (0.0, height, 0.0))


def orientation(hand, t):
    """The hand's (or its device's) orientation: heading, swing about the lateral axis, a roll."""
    side = -1.0 if hand == "left" else 1.0
    yaw = axis_angle(UP, HEADING + 0.3 * side)
    pitch = axis_angle((1.0, 0.0, 0.0), -side * math.radians(30) * math.sin(OMEGA * t))
    roll = axis_angle((0.0, 0.0, 1.0), side * math.radians(20) + 0.2 * math.sin(OMEGA * t + 1))
    return qmul(qmul(yaw, pitch), roll)


def device(hand, t, offset):
    """A device held so that the wrist is at `offset` (native metres) in the device's frame."""
    q = orientation(hand, t)
    return add(wrist(hand, t), scale(-1, rotate(q, offset))), q


# --- each platform's axes: p_source = M · p_native (and its unit) ---

IDENTITY = ((1, 0, 0), (0, 1, 0), (0, 0, 1))
# Unity: left-handed, Y up, Z forward, metres: the native frame with z negated.
UNITY = ((1, 0, 0), (0, 1, 0), (0, 0, -1))
# Unreal: left-handed, Z up, X forward, Y right, centimetres. The server's rule (negate Y, then +Z up
# to +Y) reads an Unreal (x, y, z) as native (x, z, y) / 100.
UNREAL = ((100, 0, 0), (0, 0, 100), (0, 100, 0))
# MediaPipe world landmarks: right-handed, y down, z away from the camera (native rotated 180° about x).
MEDIAPIPE = ((1, 0, 0), (0, -1, 0), (0, 0, -1))


def unity_quaternion(q):
    """Unity's Quaternion of a native rotation: the mirror z → -z turns (x, y, z, w) into (-x, -y, z, w)."""
    return (-q[0], -q[1], q[2], q[3])


def unreal_quaternion(q):
    """Unreal's FQuat of a native rotation: axis (x, y, z) becomes -(x, z, y) (a mirror: det = -1)."""
    return (-q[0], -q[2], -q[1], q[3])


def check_quaternion_formula(m, to_source):
    """The quaternion formula agrees with the position map: M·R·v = R_source·(M·v) for a few rotations
    and vectors (so the logs' orientations and positions describe one motion)."""
    for t in (0.1, 0.7, 1.3):
        q = orientation("left", t)
        qs = to_source(q)
        for v in ((1, 0, 0), (0, 1, 0), (0.3, -0.5, 0.8)):
            a = matvec(m, rotate(q, v))
            b = rotate(qs, matvec(m, v))
            assert max(abs(x - y) for x, y in zip(a, b)) < 1e-9, (m, q, v, a, b)


def fmt(v):
    return repr(float(v))


# --- the logs ---

def openxr_csv(path, offset, t0_ns=987_654_321_000):
    """OpenXR: CSV time_ns,hand,flags,px,py,pz,qx,qy,qz,qw in STAGE space (identity axes). Frame 10:
    the right hand only inferred (flags 0x3); frame 20: the left hand invalid (flags 0, garbage);
    frame 30: no right row. Returns {frame: (left confidence, right confidence)} for the odd ones."""
    special = {10: (1.0, 0.5), 20: (0.0, 1.0), 30: (1.0, 0.0)}
    lines = ["time_ns,hand,flags,px,py,pz,qx,qy,qz,qw"]
    for i, t in enumerate(times()):
        ns = t0_ns + round(t * 1e9)
        for hand in ("left", "right"):
            if i == 30 and hand == "right":
                continue
            p, q = device(hand, t, offset)
            flags = 0xF
            if i == 10 and hand == "right":
                flags = 0x3
            if i == 20 and hand == "left":
                flags, p, q = 0, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 0.0)
            lines.append(",".join([str(ns), hand, str(flags)] + [fmt(c) for c in p + q]))
    path.write_text("\n".join(lines) + "\n")
    return special


def webxr_jsonl(path, offset, t0_ms=15234.25):
    """WebXR: JSON lines {time (ms), poses: [...]} in 'local-floor' (identity axes), plus a gaze
    source (handedness 'none'). Frame 12: right pose null; frame 40: left emulatedPosition."""
    special = {12: (1.0, 0.0), 40: (0.5, 1.0)}
    with open(path, "w") as f:
        for i, t in enumerate(times()):
            poses = [{"handedness": "none", "position": {"x": 0, "y": 1.6, "z": 0, "w": 1},
                      "orientation": {"x": 0, "y": 0, "z": 0, "w": 1}, "emulatedPosition": False}]
            for hand in ("right", "left"):
                p, q = device(hand, t, offset)
                if i == 12 and hand == "right":
                    poses.append({"handedness": hand, "position": None})
                    continue
                poses.append({"handedness": hand, "position": dict(zip("xyzw", p + (1.0,))),
                              "orientation": dict(zip("xyzw", q)), "emulatedPosition": i == 40 and hand == "left"})
            f.write(json.dumps({"time": t0_ms + 1000 * t, "poses": poses}) + "\n")
    return special


def arkit_records(hand, offset, start, t0=1_700_000_000.25):
    """ARKit: one phone's records at 60 Hz from `start` s: the camera transform, column-major."""
    records = []
    for i in range(FRAMES):
        t = start + i / RATE
        p, q = device(hand, t, offset)
        r = quat_to_matrix(q)
        columns = [r[0][0], r[1][0], r[2][0], 0.0, r[0][1], r[1][1], r[2][1], 0.0, r[0][2], r[1][2], r[2][2], 0.0,
                   p[0], p[1], p[2], 1.0]
        tracking = "limited(excessiveMotion)" if i == 50 else "normal"
        records.append({"time": t0 + t, "tracking": tracking, "transform": columns})
    return records


def write_jsonl(path, records):
    path.write_text("".join(json.dumps(r) + "\n" for r in records))


def engine_csv(path, offset, m, to_source, tracked_text=("1", "0")):
    """Unity or Unreal: CSV time,hand,tracked,px,py,pz,qx,qy,qz,qw in the engine's axes and unit.
    Frame 25: the left hand untracked. Time from 3.5 s."""
    special = {25: (0.0, 1.0)}
    lines = ["time,hand,tracked,px,py,pz,qx,qy,qz,qw"]
    for i, t in enumerate(times()):
        for hand in ("left", "right"):
            p, q = device(hand, t, offset)
            tracked = not (i == 25 and hand == "left")
            lines.append(",".join([fmt(3.5 + t), hand, tracked_text[0] if tracked else tracked_text[1]] +
                                  [fmt(c) for c in matvec(m, p) + to_source(q)]))
    path.write_text("\n".join(lines) + "\n")
    return special


def mediapipe_jsonl(path, mirrored=False):
    """MediaPipe Pose world landmarks: relative to the hip centre, y down, z away; one heel on the
    floor, the other foot lifted. Frame 15: no person; frame 16: feet hidden (the last floor holds);
    wrists' visibility 0.9 (0.3 for the right one at frame 60)."""
    special = {15: (0.0, 0.0), 60: (0.9, 0.3)}
    with open(path, "w") as f:
        for i, t in enumerate(mediapipe_times()):
            if i == 15:
                f.write(json.dumps({"timestamp_ms": round(1000 * t), "pose_world_landmarks": None}) + "\n")
                continue
            hips = body(t)
            landmarks = [[0.0, -0.3, 0.0, 0.99] for _ in range(33)]

            def put(index, point, visibility):
                x, y, z = matvec(MEDIAPIPE, add(point, scale(-1, hips)))
                landmarks[index] = [(-x if mirrored else x), y, z, visibility]

            put(15, wrist("left", t), 0.9)
            put(16, wrist("right", t), 0.3 if i == 60 else 0.9)
            feet_visibility = 0.1 if i == 16 else 0.95
            planted = add(body(t), scale(0.1, RIGHT), (0.0, -body(t)[1], 0.0))  # on the floor
            lifted = add(body(t), scale(-0.1, RIGHT), (0.0, -body(t)[1] + 0.08, 0.0))
            put(29, lifted, feet_visibility)
            put(30, planted, feet_visibility)
            put(31, add(lifted, (0.0, 0.03, 0.0)), feet_visibility)
            put(32, add(planted, (0.0, 0.01, 0.0)), feet_visibility)
            if mirrored:  # the model sees a mirrored person: what it calls the left wrist is the right
                landmarks[15], landmarks[16] = landmarks[16], landmarks[15]
            f.write(json.dumps({"timestamp_ms": round(1000 * t), "pose_world_landmarks": landmarks}) + "\n")
    return special


def mediapipe_times():
    """Video frames' timestamps: whole milliseconds."""
    return [round(1000 * t) / 1000 for t in times()]


def mediapipe_expected(hand, t):
    """What a MediaPipe log can give back: the wrist over the floor, relative to the hips' travel."""
    w, h = wrist(hand, t), body(t)
    return (w[0] - h[0], w[1], w[2] - h[2])

"""MediaPipe Pose (the legacy solution's results.pose_world_landmarks, or the PoseLandmarker task's
result.pose_world_landmarks[0]): per video frame, the 33 world landmarks, logged as one JSON object
per line (docs/devices/mediapipe.md):

  {"timestamp_ms": 33, "pose_world_landmarks": [[x, y, z, visibility], ... 33 of them]}

(or each landmark as {"x":..,"y":..,"z":..,"visibility":..}; null or [] when no person was found).
Landmarks 15 and 16 are the person's own left and right wrists; x right, y DOWN, z away from the
camera, metres, origin between the hips in every frame (right-handed); visibility 0..1 becomes the
hand's confidence. The floor is each frame's lowest visible heel or toe (landmarks 29-32), so the
body's height over the floor is kept; its travel over the floor is not in the landmarks at all.
Hands (multi_hand_world_landmarks) cannot be converted: each hand's world landmarks are centred on
that hand, so they carry no wrist trajectory.
"""

from .frames import Convention
from .logs import ConvertError, field, number, read_json_lines
from .wrists import TRACKED, Frame, HandSample, require_increasing

NAME = "mediapipe"
SUMMARY = "MediaPipe Pose world landmarks (15, 16 wrists): JSON lines {timestamp_ms, pose_world_landmarks}"
CONVENTION = Convention(1.0, "-Y", "right")
HAS_ORIENTATION = False
DEFAULT_FLOOR = "feet"
LEFT_WRIST, RIGHT_WRIST = 15, 16
FEET = (29, 30, 31, 32)  # heels, then toes (foot index)
FOOT_VISIBLE = 0.5


def add_arguments(parser):
    parser.add_argument("--mirrored", action="store_true",
                        help="the frames given to MediaPipe were flipped left to right (a selfie preview): "
                        "swap the sides back and undo the reflection")


def _landmark(where, value, index):
    name = f"pose_world_landmarks[{index}]"
    if isinstance(value, dict):
        xyz = tuple(number(where, field(where, value, k), f"{name}.{k}") for k in ("x", "y", "z"))
        visibility = value.get("visibility")
    elif isinstance(value, list) and 3 <= len(value) <= 5:
        xyz = tuple(number(where, v, f"{name}[{k}]") for k, v in enumerate(value[:3]))
        visibility = value[3] if len(value) > 3 else None
    else:
        raise where.error(f"{name} should be [x, y, z, visibility] or {{\"x\":..,\"y\":..,\"z\":..,\"visibility\":..}}")
    visibility = TRACKED if visibility is None else min(1.0, max(0.0, number(where, visibility, f"{name} visibility")))
    return xyz, visibility


def read(paths, args):
    records = []  # (where, time, landmarks or None)
    for where, record in read_json_lines(paths[0]):
        time = number(where, field(where, record, "timestamp_ms"), "timestamp_ms") / 1000.0
        require_increasing(where, time, records[-1][1] if records else None, "timestamp_ms")
        landmarks = field(where, record, "pose_world_landmarks")
        if landmarks in (None, []):
            records.append((where, time, None))
            continue
        if not isinstance(landmarks, list) or len(landmarks) != 33:
            count = len(landmarks) if isinstance(landmarks, list) else "no list"
            raise where.error(f"expected the 33 pose world landmarks, found {count}"
                              + (" (a hand's 21: hand landmarks carry no wrist trajectory)" if count == 21 else ""))
        points = [_landmark(where, value, i) for i, value in enumerate(landmarks)]
        if args.mirrored:  # undo the reflection: x back, and the sides the model saw swapped
            points = [((-x, y, z), v) for (x, y, z), v in points]
            points[LEFT_WRIST], points[RIGHT_WRIST] = points[RIGHT_WRIST], points[LEFT_WRIST]
        records.append((where, time, points))

    floors = [None] * len(records)
    if args.floor == "feet":
        for i, (_, _, points) in enumerate(records):
            visible = [points[k][0][1] for k in FEET if points and points[k][1] >= FOOT_VISIBLE]
            floors[i] = max(visible) if visible else None  # y down: the lowest point has the largest y
        known = [f for f in floors if f is not None]
        if not known:
            raise ConvertError(f"{paths[0]}: no frame shows the feet (landmarks 29-32 visible): "
                               "convert with --floor calibrate (or --floor H)")
        last = known[0]  # frames before the first foot seen take the first floor, later ones the last
        for i, f in enumerate(floors):
            floors[i] = last = f if f is not None else last

    frames = []
    for (where, time, points), floor in zip(records, floors):
        hands = []
        for k in (LEFT_WRIST, RIGHT_WRIST):
            if points is None:
                hands.append(HandSample.lost(time, where))
                continue
            (x, y, z), visibility = points[k]
            hands.append(HandSample(time, (x, y - (floor or 0.0), z), None, visibility, where))
        frames.append(Frame(time, *hands))
    return frames

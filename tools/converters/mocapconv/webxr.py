"""WebXR: per XRFrame, each input source's pose — XRFrame.getPose(inputSource.gripSpace, refSpace)
for controllers, XRFrame.getJointPose(inputSource.hand.get("wrist"), refSpace) for hands — logged
as one JSON object per line (docs/devices/webxr.md):

  {"time": 1234.5, "poses": [{"handedness": "left", "position": {"x":..,"y":..,"z":..,"w":1},
                              "orientation": {"x":..,"y":..,"z":..,"w":..}, "emulatedPosition": false},
                             {"handedness": "right", "position": null}]}

time the requestAnimationFrame DOMHighResTimeStamp (milliseconds), the XRRigidTransform's position
(metres) and orientation; a pose getPose did not give (null) is lost, an emulatedPosition one
inferred. Reference space 'local-floor' or 'bounded-floor': right-handed, Y up, -Z forward,
metres, floor at y = 0 ('local': origin at the head at start, --floor calibrate).
"""

from .frames import Convention
from .logs import field, hand_name, number, read_json_lines, vector
from .wrists import INFERRED, TRACKED, Frame, HandSample, checked_quaternion, require_increasing

NAME = "webxr"
SUMMARY = "WebXR getPose(gripSpace) / getJointPose(wrist) per XRFrame: JSON lines {time, poses: [...]}"
CONVENTION = Convention(1.0, "+Y", "right")
HAS_ORIENTATION = True
DEFAULT_FLOOR = 0.0


def _hand(where, time, entry, index):
    name = f"poses[{index}]"
    if entry.get("position") is None:
        return HandSample.lost(time, where)
    position = vector(where, entry, "position", ("x", "y", "z"))
    orientation = checked_quaternion(where, vector(where, entry, "orientation", ("x", "y", "z", "w")),
                                     f"{name}.orientation")
    emulated = entry.get("emulatedPosition", False)
    if not isinstance(emulated, bool):
        raise where.error(f"{name}.emulatedPosition should be true or false, found {emulated!r}")
    return HandSample(time, position, orientation, INFERRED if emulated else TRACKED, where)


def read(paths, args):
    frames = []
    for where, record in read_json_lines(paths[0]):
        time = number(where, field(where, record, "time"), "time") / 1000.0
        require_increasing(where, time, frames[-1].time if frames else None)
        poses = field(where, record, "poses")
        if not isinstance(poses, list):
            raise where.error("\"poses\" should be a list of input sources' poses")
        frame = Frame(time, None, None)
        for index, entry in enumerate(poses):
            if not isinstance(entry, dict):
                raise where.error(f"poses[{index}] should be an object with handedness, position, orientation")
            handedness = field(where, entry, "handedness")
            if handedness == "none":  # gaze or screen input: not a hand
                continue
            hand = hand_name(where, handedness, f"poses[{index}].handedness")
            if getattr(frame, hand) is not None:
                raise where.error(f"two {hand} input sources in one frame")
            setattr(frame, hand, _hand(where, time, entry, index))
        frames.append(frame)
    return frames

"""OpenXR (Meta Quest and other runtimes): per frame, each hand's grip pose (controllers,
xrLocateSpace) or wrist joint (hand tracking, XR_HAND_JOINT_WRIST_EXT of xrLocateHandJointsEXT),
located in a STAGE or LOCAL_FLOOR reference space, logged as CSV (docs/devices/openxr.md):

  time_ns,hand,flags,px,py,pz,qx,qy,qz,qw

time_ns the XrTime located at (nanoseconds), flags the XrSpaceLocationFlags, the XrPosef's position
(metres) and orientation (x, y, z, w). Space: right-handed, Y up, -Z forward, metres; the floor at
y = 0 in STAGE and LOCAL_FLOOR (LOCAL: origin at the head at start, --floor calibrate).
"""

from .frames import Convention
from .logs import number
from .pose_rows import read_pose_rows
from .wrists import INFERRED, TRACKED

NAME = "openxr"
SUMMARY = "OpenXR grip poses or hand-tracking wrist joints: CSV time_ns,hand,flags,px,py,pz,qx,qy,qz,qw"
CONVENTION = Convention(1.0, "+Y", "right")
HAS_ORIENTATION = True
DEFAULT_FLOOR = 0.0

ORIENTATION_VALID, POSITION_VALID, ORIENTATION_TRACKED, POSITION_TRACKED = 0x1, 0x2, 0x4, 0x8


def location_status(where, text):
    """XrSpaceLocationFlags: a position not VALID is lost; VALID but not TRACKED (the runtime
    inferred it) is INFERRED; both bits, TRACKED."""
    value = number(where, text, "flags")
    if value != int(value) or not 0 <= value < 2**64:
        raise where.error(f"flags should be the XrSpaceLocationFlags as an integer, found \"{text}\"")
    flags = int(value)
    confidence = TRACKED if flags & POSITION_TRACKED else INFERRED
    return bool(flags & POSITION_VALID), bool(flags & ORIENTATION_VALID), confidence


def read(paths, args):
    return read_pose_rows(paths[0], "time_ns", 1e-9, "flags", location_status)

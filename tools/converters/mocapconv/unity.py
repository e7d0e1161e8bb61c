"""Unity (XR Interaction Toolkit / UnityEngine.XR.InputDevices): per frame, each hand device's
CommonUsages.devicePosition and deviceRotation (tracking space of the XR Origin) and isTracked,
logged as CSV (docs/devices/unity.md):

  time,hand,tracked,px,py,pz,qx,qy,qz,qw

time in seconds (Time.realtimeSinceStartupAsDouble), tracked 1/0 (or true/false), the Vector3
(metres) and the Quaternion (x, y, z, w). Unity's frame is LEFT-handed, Y up, Z forward, metres;
with the XR Origin's tracking origin mode Floor the floor is at y = 0 (Device: --floor calibrate).
"""

from .frames import Convention
from .logs import flag
from .pose_rows import read_pose_rows
from .wrists import LOST, TRACKED

NAME = "unity"
SUMMARY = "Unity XR input devices' devicePosition/deviceRotation: CSV time,hand,tracked,px,py,pz,qx,qy,qz,qw"
CONVENTION = Convention(1.0, "+Y", "left")
HAS_ORIENTATION = True
DEFAULT_FLOOR = 0.0


def tracked_status(where, text):
    tracked = flag(where, text, "tracked")
    return tracked, tracked, TRACKED if tracked else LOST


def read(paths, args):
    return read_pose_rows(paths[0], "time", 1.0, "tracked", tracked_status)

"""Unreal Engine: per tick, each UMotionControllerComponent's world transform
(GetComponentLocation, GetComponentQuat) and IsTracked, logged as CSV (docs/devices/unreal.md):

  time,hand,tracked,px,py,pz,qx,qy,qz,qw

time in seconds (FPlatformTime::Seconds), tracked 1/0, the FVector (centimetres) and the FQuat
(X, Y, Z, W). Unreal's frame is LEFT-handed, Z up, X forward, Y right, centimetres; the floor at
z = 0 in a level built on it.
"""

from .frames import Convention
from .pose_rows import read_pose_rows
from .unity import tracked_status

NAME = "unreal"
SUMMARY = "Unreal motion controller components' world transforms: CSV time,hand,tracked,px,py,pz,qx,qy,qz,qw (cm)"
CONVENTION = Convention(0.01, "+Z", "left")
HAS_ORIENTATION = True
DEFAULT_FLOOR = 0.0


def read(paths, args):
    return read_pose_rows(paths[0], "time", 1.0, "tracked", tracked_status)

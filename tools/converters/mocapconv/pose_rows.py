"""CSV logs of one pose per hand per frame (OpenXR, Unity, Unreal):

  TIME,hand,STATUS,px,py,pz,qx,qy,qz,qw

TIME in the source's clock unit, hand left/right, STATUS what the source says about tracking (a
source module turns it into position valid, orientation valid and a confidence), the position in
the source's frame and unit, the orientation quaternion x, y, z, w. Both hands of one frame carry
the same TIME; a hand without a row in a frame is lost there.
"""

from .logs import hand_name, number, read_csv_rows
from .wrists import HandSample, checked_quaternion, frames_from_hand_rows

POSITION = ("px", "py", "pz")
ORIENTATION = ("qx", "qy", "qz", "qw")


def read_pose_rows(path, time_column, seconds_per_unit, status_column, status):
    """Frames of a per-hand pose CSV. `status(where, text)` gives (position valid, orientation
    valid, confidence); the values of what is not valid are not read (runtimes leave them undefined)."""

    def samples():
        for where, row in read_csv_rows(path, (time_column, "hand", status_column) + POSITION + ORIENTATION):
            time = number(where, row[time_column], time_column) * seconds_per_unit
            hand = hand_name(where, row["hand"])
            position_valid, orientation_valid, confidence = status(where, row[status_column])
            if not position_valid:
                yield hand, HandSample.lost(time, where)
                continue
            position = tuple(number(where, row[c], c) for c in POSITION)
            orientation = None
            if orientation_valid:
                orientation = checked_quaternion(where, tuple(number(where, row[c], c) for c in ORIENTATION))
            yield hand, HandSample(time, position, orientation, confidence, where)

    return frames_from_hand_rows(samples())

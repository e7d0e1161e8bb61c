"""What every source is read into, and the one CSV they are all written as.

A source module reads its log into hand samples in the source's own frame and clock; this module
groups them into frames (both hands at one time), applies a device offset, converts to the native
frame (frames.py) and writes the CSV `mocap reconstruct --csv` reads (client/wrist_input/
wrist_source.h; docs/getting-started.md "Wrist samples from a CSV or a device log"):

  time,left_x,left_y,left_z,right_x,right_y,right_z,left_confidence,right_confidence
      [,left_qw,left_qx,left_qy,left_qz,right_qw,right_qx,right_qy,right_qz]

time in seconds from the log's first sample; positions in metres, right-handed, Y up, floor at
y = 0 when the source's floor is known; confidences 1 (tracked), 0.5 (the source says inferred),
0 (lost: position `nan`, orientation cells empty); orientations where the source has them.
"""

from dataclasses import dataclass
from typing import Optional, Tuple

from .frames import quat_norm, quat_normalized, quat_rotate, quat_slerp
from .logs import ConvertError

TRACKED, INFERRED, LOST = 1.0, 0.5, 0.0

Vec3 = Tuple[float, float, float]
Quat = Tuple[float, float, float, float]  # x, y, z, w


@dataclass
class HandSample:
    """One hand at one time, in the source's frame, units and clock."""
    time: float
    position: Optional[Vec3]  # None: lost
    orientation: Optional[Quat]  # None: the source has none, or it was not valid
    confidence: float
    where: object = None  # logs.Where, for messages

    @staticmethod
    def lost(time, where=None):
        return HandSample(time, None, None, LOST, where)


@dataclass
class Frame:
    time: float
    left: Optional[HandSample]
    right: Optional[HandSample]


def checked_quaternion(where, q, name="orientation"):
    """A unit quaternion as logged (x, y, z, w), normalised; an error when it is far from unit
    length (Euler angles or a matrix logged instead, or the components out of order)."""
    n = quat_norm(q)
    if abs(n - 1) > 0.01:
        raise where.error(f"{name} is not a unit quaternion (length {n:.4g}): expected x, y, z, w of a rotation")
    return quat_normalized(q)


def require_increasing(where, time, previous, what="time"):
    if previous is not None and time <= previous:
        raise where.error(f"{what} {time:.9g} does not increase (the sample before was at {previous:.9g}): "
                          "samples out of order, or a clock that went back")


def frames_from_hand_rows(samples):
    """Frames from per-hand rows in log order: (hand, HandSample) with both hands of a frame at the
    same time. A hand without a row in a frame is lost there."""
    frames = []
    for hand, sample in samples:
        if frames and sample.time == frames[-1].time:
            frame = frames[-1]
            if getattr(frame, hand) is not None:
                raise sample.where.error(f"a second {hand} sample at time {sample.time:.9g} "
                                         f"(the first on line {getattr(frame, hand).where.line})")
        else:
            require_increasing(sample.where, sample.time, frames[-1].time if frames else None)
            frame = Frame(sample.time, None, None)
            frames.append(frame)
        setattr(frame, hand, sample)
    return frames


def _at(samples, index, time, max_gap):
    """The hand at `time` from its samples (sorted), interpolated between the samples around it when
    both are tracked and at most max_gap seconds apart; lost otherwise."""
    if index < len(samples) and samples[index].time == time:
        return samples[index]
    if index == 0 or index == len(samples):
        return HandSample.lost(time)
    a, b = samples[index - 1], samples[index]
    if a.position is None or b.position is None or b.time - a.time > max_gap:
        return HandSample.lost(time)
    f = (time - a.time) / (b.time - a.time)
    position = tuple(x + f * (y - x) for x, y in zip(a.position, b.position))
    orientation = None
    if a.orientation is not None and b.orientation is not None:
        orientation = quat_slerp(a.orientation, b.orientation, f)
    return HandSample(time, position, orientation, min(a.confidence, b.confidence), a.where)


def frames_from_two_streams(left, right, max_gap=0.1):
    """Frames from two hands sampled at their own times (two phones): at every time either hand has
    a sample, the other is interpolated linearly (orientation by slerp) between its samples around
    it, or lost when they are more than max_gap seconds apart or outside its log."""
    times = sorted({s.time for s in left} | {s.time for s in right})
    frames, i, j = [], 0, 0
    for t in times:
        while i < len(left) and left[i].time < t:
            i += 1
        while j < len(right) and right[j].time < t:
            j += 1
        frames.append(Frame(t, _at(left, i, t, max_gap), _at(right, j, t, max_gap)))
    return frames


@dataclass
class Options:
    """What the user declares on the converter's command line."""
    device_offset: Optional[Vec3] = None  # from the tracked point to the wrist, device frame, source units
    floor: object = 0.0  # the floor's coordinate on the source's up axis (source units), or 'calibrate'


@dataclass
class NativeHand:
    position: Optional[Vec3]
    orientation: Optional[Quat]
    confidence: float


def _hand_to_native(sample, convention, options, floor_height):
    if sample is None or sample.position is None or sample.confidence <= 0:
        return NativeHand(None, None, LOST)
    position = sample.position
    if options.device_offset is not None:
        if sample.orientation is None:  # no valid orientation: the wrist cannot be placed
            return NativeHand(None, None, LOST)
        offset = quat_rotate(sample.orientation, options.device_offset)
        position = tuple(p + o for p, o in zip(position, offset))
    x, y, z = convention.position_to_native(position)
    orientation = None if sample.orientation is None else convention.rotation_to_native(sample.orientation)
    return NativeHand((x, y - floor_height, z), orientation, sample.confidence)


def to_native(frames, convention, options):
    """Rows (time from the first frame, left NativeHand, right NativeHand) in the native frame."""
    if not frames:
        raise ConvertError("the log holds no samples")
    floor = 0.0 if options.floor == "calibrate" else convention.up_to_native_height(options.floor)
    t0 = frames[0].time
    return [(f.time - t0, _hand_to_native(f.left, convention, options, floor),
             _hand_to_native(f.right, convention, options, floor)) for f in frames]


HEADER = "time,left_x,left_y,left_z,right_x,right_y,right_z,left_confidence,right_confidence"
ORIENTATION_HEADER = "left_qw,left_qx,left_qy,left_qz,right_qw,right_qx,right_qy,right_qz"


def write_wrist_csv(out, rows, with_orientation, comments=()):
    """Writes rows (to_native's) to the text stream `out` as the CSV `mocap reconstruct --csv` reads."""
    for comment in comments:
        out.write(f"# {comment}\n")
    out.write(HEADER + ("," + ORIENTATION_HEADER if with_orientation else "") + "\n")
    previous = None
    for time, left, right in rows:
        stamp = f"{time:.6f}"
        if previous is not None and float(stamp) <= float(previous):
            raise ConvertError(f"two samples {time - float(previous):.2g} s apart round to one time "
                               f"({stamp} s): the CSV keeps microseconds")
        previous = stamp
        fields = [stamp]
        for hand in (left, right):
            fields += ["nan"] * 3 if hand.position is None else [f"{c:.6f}" for c in hand.position]
        fields += [f"{hand.confidence:.4f}".rstrip("0").rstrip(".") for hand in (left, right)]
        if with_orientation:
            for hand in (left, right):
                q = hand.orientation
                fields += ["", "", "", ""] if q is None else [f"{c:.7f}" for c in (q[3], q[0], q[1], q[2])]
        out.write(",".join(fields) + "\n")


"""mocap_convert.py SOURCE LOG [LOG2] -o OUT.csv: a device log to the CSV `mocap reconstruct --csv`
reads, in the server's own frame (metres, right-handed, Y up), so that no --input-frame is needed.
docs/devices/README.md describes each source's log and conventions.
"""

import argparse
import io
import math
import os
import sys

from . import arkit, mediapipe, openxr, unity, unreal, webxr
from .logs import ConvertError
from .wrists import Options, to_native, write_wrist_csv

SOURCES = {m.NAME: m for m in (openxr, webxr, arkit, unity, unreal, mediapipe)}
MAX_DEVICE_OFFSET_METRES = 0.5  # the server's limit (motion/frames/input_frame.h)


def _offset(text):
    try:
        values = tuple(float(v) for v in text.split(","))
    except ValueError:
        values = ()
    if len(values) != 3 or not all(math.isfinite(v) for v in values):
        raise argparse.ArgumentTypeError(f"expected X,Y,Z (three numbers), found \"{text}\"")
    return values


def _floor(choices):
    def parse(text):
        if text in choices:
            return text
        try:
            value = float(text)
        except ValueError:
            value = math.nan
        if not math.isfinite(value):
            raise argparse.ArgumentTypeError(f"expected a number or {' or '.join(choices)}, found \"{text}\"")
        return value
    return parse


def parser():
    p = argparse.ArgumentParser(
        prog="mocap_convert.py",
        description="Convert a device log to the wrist CSV of `mocap reconstruct --csv`, in the server's own frame "
        "(metres, right-handed, Y up): docs/devices/README.md.")
    sub = p.add_subparsers(dest="source", required=True, metavar="SOURCE")
    for name, module in SOURCES.items():
        s = sub.add_parser(name, help=module.SUMMARY, description=module.__doc__,
                           formatter_class=argparse.RawDescriptionHelpFormatter)
        s.add_argument("logs", nargs="+", metavar="LOG",
                       help=getattr(module, "INPUTS_HELP", "the log"))
        s.add_argument("-o", "--output", required=True, metavar="OUT.csv", help="the CSV to write ('-': stdout)")
        floor_choices = ("calibrate", "feet") if module.DEFAULT_FLOOR == "feet" else ("calibrate",)
        s.add_argument("--floor", type=_floor(floor_choices), default=module.DEFAULT_FLOOR,
                       help="the floor's coordinate on the source's up axis, in its units; 'calibrate': unknown, "
                       "left to `mocap reconstruct --floor calibrate`"
                       + ("; 'feet': each frame's lowest visible heel or toe" if "feet" in floor_choices else "")
                       + f" (default: {module.DEFAULT_FLOOR})")
        if module.HAS_ORIENTATION:
            s.add_argument("--device-offset", type=_offset, metavar="X,Y,Z",
                           help="the logged pose is a device's (a controller's grip, a phone's camera): the offset "
                           "from it to the wrist in the device's own axes and the log's units; the CSV then holds "
                           "the wrists")
        s.add_argument("--quiet", action="store_true", help="print nothing but errors")
        if hasattr(module, "add_arguments"):
            module.add_arguments(s)
    return p


def convert(source, logs, floor=None, device_offset=None, mirrored=False):
    """The CSV text of a conversion and the notes about it (for the tests and the command line)."""
    module = SOURCES[source]
    args = argparse.Namespace(floor=module.DEFAULT_FLOOR if floor is None else floor, mirrored=mirrored)
    if not 1 <= len(logs) <= getattr(module, "MAX_INPUTS", 1):
        raise ConvertError(f"{source} takes {getattr(module, 'INPUTS_HELP', 'one log')}; {len(logs)} given")
    if device_offset is not None:
        length = module.CONVENTION.metres_per_unit * math.sqrt(sum(v * v for v in device_offset))
        if length > MAX_DEVICE_OFFSET_METRES:
            raise ConvertError(f"--device-offset is {length:.2f} m long in the log's units: at most "
                               f"{MAX_DEVICE_OFFSET_METRES} m (a hand is not that long)")
    frames = module.read(logs, args)
    options = Options(device_offset=device_offset, floor=0.0 if args.floor == "feet" else args.floor)
    rows = to_native(frames, module.CONVENTION, options)
    floor_known = args.floor != "calibrate"
    comments = [
        f"converted by tools/converters/mocap_convert.py {source} from {', '.join(os.path.basename(str(x)) for x in logs)}",
        "time: seconds from the first sample; positions: metres, right-handed, Y up (the server's own frame)",
        "floor: at y = 0" if floor_known else "floor: unknown, reconstruct with --floor calibrate",
    ]
    if module.HAS_ORIENTATION:
        comments.append("positions: the wrists (device offset applied), orientations: the devices'"
                        if device_offset else "positions and orientations: the logged poses'")
    out = io.StringIO()
    write_wrist_csv(out, rows, module.HAS_ORIENTATION, comments)
    tracked = [sum(1 for row in rows if row[k].confidence > 0) for k in (1, 2)]
    notes = {"samples": len(rows), "seconds": rows[-1][0], "tracked": tracked, "floor_known": floor_known}
    return out.getvalue(), notes


def main(argv=None):
    args = parser().parse_args(argv)
    try:
        text, notes = convert(args.source, args.logs, args.floor, getattr(args, "device_offset", None),
                              getattr(args, "mirrored", False))
    except ConvertError as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    if args.output == "-":
        sys.stdout.write(text)
    else:
        try:
            with open(args.output, "w", encoding="utf-8", newline="\n") as f:
                f.write(text)
        except OSError as e:
            print(f"error: {args.output}: cannot write ({e.strerror})", file=sys.stderr)
            return 1
    if not args.quiet and args.output != "-":
        n = notes["samples"]
        print(f"wrote {args.output}: {n} samples over {notes['seconds']:.2f} s; left hand tracked in "
              f"{notes['tracked'][0]}, right in {notes['tracked'][1]}", file=sys.stderr)
        floor = "" if notes["floor_known"] else " --floor calibrate"
        print(f"next: mocap reconstruct --database DATABASE --csv {args.output}{floor} --lag 5 -o NAME",
              file=sys.stderr)
    return 0

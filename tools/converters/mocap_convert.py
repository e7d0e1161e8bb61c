#!/usr/bin/env python3
"""Converts a device log (OpenXR, WebXR, ARKit, Unity, Unreal, MediaPipe) to the wrist CSV that
`mocap reconstruct --csv` reads, in the server's own frame. Python 3 standard library only.

  python3 tools/converters/mocap_convert.py SOURCE LOG [LOG2] -o OUT.csv [--device-offset X,Y,Z] [--floor H|calibrate]

What to log on each platform, its conventions and the commands: docs/devices/README.md.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from mocapconv.cli import main  # noqa: E402

if __name__ == "__main__":
    sys.exit(main())

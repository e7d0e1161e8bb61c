"""Wrist samples from a CSV file, in the format `mocap reconstruct --csv` reads.

One header line naming the columns, exactly these in this order (the optional groups at the end):

    time,left_x,left_y,left_z,right_x,right_y,right_z[,left_confidence,right_confidence[,left_qw,left_qx,left_qy,left_qz,right_qw,right_qx,right_qy,right_qz]]

then one sample per line: time in seconds (strictly increasing), wrist positions (metres, Y up,
floor at y = 0 unless the session declares another input frame), confidences 0..1 and device
orientations (empty cells leave them unset). Blank lines and lines starting with '#' are skipped.
docs/getting-started.md ("Wrist samples from a CSV or a device log") has the details.
"""
from __future__ import annotations

import math
import os
import re
from typing import Iterable, List, Union

from mocap_client.v1 import reconstruction_pb2

COLUMNS = ("time", "left_x", "left_y", "left_z", "right_x", "right_y", "right_z",
           "left_confidence", "right_confidence",
           "left_qw", "left_qx", "left_qy", "left_qz", "right_qw", "right_qx", "right_qy", "right_qz")
_POSITION_COLUMNS, _CONFIDENCE_COLUMNS = 7, 9
HEADER = ("time,left_x,left_y,left_z,right_x,right_y,right_z[,left_confidence,right_confidence"
          "[,left_qw,left_qx,left_qy,left_qz,right_qw,right_qx,right_qy,right_qz]]")
# A decimal number, nan or inf (any case, optional sign): what the C++ reader accepts.
_NUMBER = re.compile(r"[+-]?((\d+\.?\d*|\.\d+)([eE][+-]?\d+)?|nan|inf|infinity)", re.IGNORECASE)


def read_wrist_csv(path: Union[str, os.PathLike]) -> List[reconstruction_pb2.WristSample]:
    """The samples of a wrist CSV file. Raises ValueError naming the file and line of a problem."""
    with open(path, encoding="utf-8", newline="") as stream:
        return parse_wrist_csv(stream, os.fspath(path))


def parse_wrist_csv(lines: Iterable[str], name: str = "<csv>") -> List[reconstruction_pb2.WristSample]:
    """The samples of a wrist CSV given as lines of text (a file object, a list of strings)."""
    samples = []
    columns = 0  # 0 until the header has been read
    for number, line in enumerate(lines, start=1):
        text = line.rstrip("\r\n").strip(" \t")
        if not text or text.startswith("#"):
            continue
        fields = [field.strip(" \t") for field in text.split(",")]
        if columns == 0:
            if len(fields) not in (_POSITION_COLUMNS, _CONFIDENCE_COLUMNS, len(COLUMNS)) or \
                    tuple(fields) != COLUMNS[:len(fields)]:
                raise ValueError(f'{name}:{number}: expected the header {HEADER}, found "{text}"')
            columns = len(fields)
            continue
        if len(fields) != columns:
            raise ValueError(f"{name}:{number}: expected {columns} fields as in the header, found {len(fields)}")
        values = [None] * len(COLUMNS)
        for i, field in enumerate(fields):
            if i >= _POSITION_COLUMNS and not field:
                continue  # confidence or orientation left unset
            if not _NUMBER.fullmatch(field):
                raise ValueError(f'{name}:{number}: {COLUMNS[i]} is not a number: "{field}"')
            value = float(field)
            if _POSITION_COLUMNS <= i < _CONFIDENCE_COLUMNS and math.isfinite(value) and not 0.0 <= value <= 1.0:
                raise ValueError(f"{name}:{number}: {COLUMNS[i]} must lie in 0..1, found {field}")
            values[i] = value
        sample = reconstruction_pb2.WristSample(time=values[0])
        sample.left.x, sample.left.y, sample.left.z = values[1:4]
        sample.right.x, sample.right.y, sample.right.z = values[4:7]
        if values[7] is not None:
            sample.left_confidence = values[7]
        if values[8] is not None:
            sample.right_confidence = values[8]
        for side, orientation in enumerate((sample.left_orientation, sample.right_orientation)):
            q = values[_CONFIDENCE_COLUMNS + 4 * side:_CONFIDENCE_COLUMNS + 4 * side + 4]
            if any(v is not None for v in q):
                orientation.w, orientation.x, orientation.y, orientation.z = (v or 0.0 for v in q)
        samples.append(sample)
    if columns == 0:
        raise ValueError(f"{name}: empty file, expected the header {HEADER}")
    if not samples:
        raise ValueError(f"{name}: no samples after the header")
    return samples

"""Reading device logs line by line, with errors that name the file and line.

Two shapes of log: CSV with a header (one row per hand per frame: OpenXR, Unity, Unreal) and JSON
lines (one object per frame or per phone sample: WebXR, ARKit, MediaPipe). Blank lines and lines
starting with '#' are skipped in both.
"""

import csv
import json
import math


class ConvertError(Exception):
    """A log that cannot be converted; the message starts with FILE:LINE when a line is at fault."""


class Where:
    """A place in a log: FILE:LINE, for messages."""

    def __init__(self, path, line):
        self.path, self.line = str(path), line

    def __str__(self):
        return f"{self.path}:{self.line}"

    def error(self, what):
        return ConvertError(f"{self}: {what}")


def _open(path):
    try:
        return open(path, encoding="utf-8-sig", newline="")
    except OSError as e:
        raise ConvertError(f"{path}: cannot read the file ({e.strerror})") from None


def read_json_lines(path):
    """Yields (Where, object) for each JSON object of a JSON-lines file."""
    with _open(path) as f:
        found = False
        for number, line in enumerate(f, start=1):
            text = line.strip()
            if not text or text.startswith("#"):
                continue
            where = Where(path, number)
            try:
                value = json.loads(text)
            except json.JSONDecodeError as e:
                raise where.error(f"not a JSON object: {e.msg} at column {e.colno}") from None
            if not isinstance(value, dict):
                raise where.error(f"expected one JSON object per line, found {type(value).__name__}")
            found = True
            yield where, value
    if not found:
        raise ConvertError(f"{path}: no records (an empty log?)")


def read_csv_rows(path, columns, optional=()):
    """Yields (Where, {column: text}) for each row of a CSV log whose header names `columns` (in any
    order, among others; `optional` ones may be missing and then read as '')."""
    with _open(path) as f:
        header, found = None, False
        reader = csv.reader(f)
        for fields in reader:
            where = Where(path, reader.line_num)
            fields = [field.strip() for field in fields]
            if not fields or fields == [""] or fields[0].startswith("#"):
                continue
            if header is None:
                missing = [c for c in columns if c not in fields]
                if missing:
                    raise where.error(f"the header lacks {', '.join(missing)}: expected the columns "
                                      f"{','.join(columns)} (found \"{','.join(fields)}\")")
                header = fields
                continue
            if len(fields) != len(header):
                raise where.error(f"expected {len(header)} fields as in the header, found {len(fields)} "
                                  "(a decimal comma? write numbers with a '.')")
            row = dict(zip(header, fields))
            for c in optional:
                row.setdefault(c, "")
            found = True
            yield where, row
    if header is None or not found:
        raise ConvertError(f"{path}: no samples (expected a header line {','.join(columns)}, then one line per sample)")


def number(where, value, name):
    """A finite number from a JSON value or CSV text; an error naming the field otherwise."""
    if isinstance(value, bool) or value is None:
        raise where.error(f"{name} is missing" if value is None else f"{name} is not a number: {value!r}")
    if isinstance(value, str):
        try:
            value = float(value)
        except ValueError:
            raise where.error(f"{name} is not a number: \"{value}\"") from None
    if not isinstance(value, (int, float)):
        raise where.error(f"{name} is not a number: {value!r}")
    if not math.isfinite(value):
        raise where.error(f"{name} is {value}, not a finite number (a sample the source says it tracked)")
    return float(value)


def field(where, record, path):
    """record['a']['b'] for path 'a.b'; an error naming the missing field."""
    value = record
    for key in path.split("."):
        if not isinstance(value, dict) or key not in value:
            raise where.error(f"missing field \"{path}\"")
        value = value[key]
    return value


def vector(where, record, path, keys):
    """Numbers record[path][k] for k in keys (a JSON object like {"x":..,"y":..,"z":..})."""
    value = field(where, record, path)
    if not isinstance(value, dict):
        raise where.error(f"\"{path}\" should be an object with {', '.join(keys)}")
    return tuple(number(where, field(where, value, k), f"{path}.{k}") for k in keys)


def hand_name(where, text, name="hand"):
    """'left' or 'right' (any case); an error naming the value otherwise."""
    hand = str(text).strip().lower()
    if hand not in ("left", "right"):
        raise where.error(f"unknown {name} \"{text}\": expected left or right")
    return hand


def flag(where, text, name):
    """A logged boolean: 1/0, true/false (any case)."""
    value = str(text).strip().lower()
    if value in ("1", "true"):
        return True
    if value in ("0", "false"):
        return False
    raise where.error(f"{name} should be 1/0 or true/false, found \"{text}\"")

"""tools/converters (docs/devices): every source's synthetic log converts back to the canonical
wrist trajectory (positions within 1 mm, orientations within 0.1°, tracking as confidences),
malformed logs fail naming the line, and the converted CSVs are read by mocap's own CSV reader.

  python3 -m unittest discover -s tests/tools/converters      (ctest: device_log_converters)

MOCAP_CLI=build/client/mocap runs the CSVs through `mocap reconstruct --csv` against a closed port:
the CLI reads the whole CSV (client/wrist_input) before it first calls the server, so a CSV it
accepts fails only at the connection, and one it refuses fails naming the file and line.
"""

import csv
import json
import math
import os
import re
import socket
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[2]
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(ROOT / "tools" / "converters"))

import synthetic as syn  # noqa: E402
from mocapconv import cli  # noqa: E402
from mocapconv.logs import ConvertError  # noqa: E402

CONVERTER = ROOT / "tools" / "converters" / "mocap_convert.py"
OFFSET = (0.01, -0.02, 0.09)  # device to wrist, in the device's native-frame axes (metres)
MM, DEGREE = 0.001, 1.0


def read_csv(text):
    """The converted CSV as (header, rows of floats or None for an empty cell)."""
    lines = [line for line in text.splitlines() if line.strip() and not line.startswith("#")]
    header = lines[0].split(",")
    rows = [[float(v) if v else None for v in row] for row in csv.reader(lines[1:])]
    return header, rows


class ConverterTest(unittest.TestCase):
    maxDiff = None

    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = Path(self.tmp.name)

    def tearDown(self):
        self.tmp.cleanup()

    def check(self, text, expected_times, expected, special=None, orientation=True, default=(1.0, 1.0)):
        """Rows against the canonical motion: expected(hand, t, row) -> (position, quaternion or None);
        confidences `default` but in the rows of `special` ({row: (left, right)})."""
        special = special or {}
        header, rows = read_csv(text)
        columns = ["time", "left_x", "left_y", "left_z", "right_x", "right_y", "right_z", "left_confidence",
                   "right_confidence"]
        if orientation:
            columns += [f"{h}_q{c}" for h in ("left", "right") for c in "wxyz"]
        self.assertEqual(header, columns)
        self.assertEqual(len(rows), len(expected_times))
        worst_mm, worst_degree = 0.0, 0.0
        for i, (row, t) in enumerate(zip(rows, expected_times)):
            self.assertAlmostEqual(row[0], t - expected_times[0], delta=2e-6, msg=f"row {i} time")
            confidences = special.get(i, default)
            for k, hand in enumerate(("left", "right")):
                self.assertAlmostEqual(row[7 + k], confidences[k], places=4, msg=f"row {i} {hand} confidence")
                position = row[1 + 3 * k:4 + 3 * k]
                if confidences[k] == 0:
                    self.assertTrue(all(math.isnan(c) for c in position), f"row {i} {hand}: a lost hand is nan")
                    if orientation:
                        self.assertEqual(row[9 + 4 * k:13 + 4 * k], [None] * 4, f"row {i} {hand}")
                    continue
                want_position, want_orientation = expected(hand, t, i)
                error = math.dist(position, want_position)
                worst_mm = max(worst_mm, error / MM)
                self.assertLess(error, MM, f"row {i} {hand}: {position} against {want_position}")
                if orientation:
                    qw, qx, qy, qz = row[9 + 4 * k:13 + 4 * k]
                    angle = syn.angle_between((qx, qy, qz, qw), want_orientation)
                    worst_degree = max(worst_degree, angle)
                    self.assertLess(angle, 0.1 * DEGREE, f"row {i} {hand} orientation")
        return worst_mm, worst_degree

    @staticmethod
    def canonical(hand, t, i):
        return syn.wrist(hand, t), syn.orientation(hand, t)

    def convert(self, source, *logs, **options):
        text, _ = cli.convert(source, [str(p) for p in logs], **options)
        (self.dir / f"{source}.csv").write_text(text)
        return text

    # --- each source back to the canonical motion ---

    def test_openxr_grip_poses_with_device_offset(self):
        log = self.dir / "openxr.csv"
        special = syn.openxr_csv(log, OFFSET)
        text = self.convert("openxr", log, device_offset=OFFSET)
        self.check(text, syn.times(), self.canonical, special)

    def test_openxr_wrist_joints_without_offset(self):
        log = self.dir / "openxr_hands.csv"
        special = syn.openxr_csv(log, (0.0, 0.0, 0.0))
        text = self.convert("openxr", log)
        self.check(text, syn.times(), self.canonical, special)
        self.assertIn("# floor: at y = 0", text)

    def test_webxr(self):
        log = self.dir / "webxr.jsonl"
        special = syn.webxr_jsonl(log, OFFSET)
        self.check(self.convert("webxr", log, device_offset=OFFSET), syn.times(), self.canonical, special)

    def test_arkit_two_phones_on_one_clock(self):
        # Two phones at 60 Hz, the right one's frames 7 ms after the left's: each hand is interpolated
        # onto the other's times (within 0.3 mm and 0.05° here), and a phone's samples are lost
        # outside its own log.
        left, right = self.dir / "left.jsonl", self.dir / "right.jsonl"
        syn.write_jsonl(left, syn.arkit_records("left", OFFSET, 0.0))
        syn.write_jsonl(right, syn.arkit_records("right", OFFSET, 0.007))
        times = sorted([i / syn.RATE for i in range(syn.FRAMES)] + [0.007 + i / syn.RATE for i in range(syn.FRAMES)])
        # Frame 50 of each phone "limited" (rows 100 and 101), and the rows interpolated from them.
        special = {0: (1.0, 0.0), len(times) - 1: (0.0, 1.0), 99: (0.5, 1.0), 100: (0.5, 0.5), 101: (0.5, 0.5),
                   102: (1.0, 0.5)}
        text = self.convert("arkit", left, right, device_offset=OFFSET)
        self.check(text, times, self.canonical, special)
        self.assertIn("# floor: unknown, reconstruct with --floor calibrate", text)

    def test_arkit_one_log_with_a_hand_field(self):
        records = []
        for hand, start in (("left", 0.0), ("right", 0.007)):
            for r in syn.arkit_records(hand, OFFSET, start):
                records.append(dict(r, hand=hand))
        records.sort(key=lambda r: r["time"])  # a relay logging both phones as their frames arrive
        log = self.dir / "phones.jsonl"
        syn.write_jsonl(log, records)
        times = sorted(r["time"] - records[0]["time"] for r in records)
        special = {0: (1.0, 0.0), len(times) - 1: (0.0, 1.0), 99: (0.5, 1.0), 100: (0.5, 0.5), 101: (0.5, 0.5),
                   102: (1.0, 0.5)}
        self.check(self.convert("arkit", log, device_offset=OFFSET, floor=0.0), times, self.canonical, special)

    def test_unity(self):
        syn.check_quaternion_formula(syn.UNITY, syn.unity_quaternion)
        self.assertLess(syn.det(syn.UNITY), 0)  # left-handed
        self.assertEqual(syn.matvec(syn.UNITY, syn.UP), (0, 1, 0))  # Y up
        log = self.dir / "unity.csv"
        offset = syn.matvec(syn.UNITY, OFFSET)  # the same offset in Unity's axes
        special = syn.engine_csv(log, OFFSET, syn.UNITY, syn.unity_quaternion, ("True", "False"))
        self.check(self.convert("unity", log, device_offset=offset), syn.times(), self.canonical, special)

    def test_unreal(self):
        syn.check_quaternion_formula(syn.UNREAL, syn.unreal_quaternion)
        self.assertLess(syn.det(syn.UNREAL), 0)  # left-handed
        self.assertEqual(syn.matvec(syn.UNREAL, syn.UP), (0, 0, 100))  # Z up, centimetres
        log = self.dir / "unreal.csv"
        offset = syn.matvec(syn.UNREAL, OFFSET)  # the same offset in Unreal's axes and centimetres
        special = syn.engine_csv(log, OFFSET, syn.UNREAL, syn.unreal_quaternion)
        self.check(self.convert("unreal", log, device_offset=offset), syn.times(), self.canonical, special)

    def mediapipe_expected(self, hand, t, i):
        x, y, z = syn.mediapipe_expected(hand, t)
        if i == 16:  # feet hidden: the floor of frame 14 (15 had no person) holds
            y += syn.body(syn.mediapipe_times()[14])[1] - syn.body(t)[1]
        return (x, y, z), None

    def test_mediapipe_pose(self):
        log = self.dir / "pose.jsonl"
        special = syn.mediapipe_jsonl(log)
        text = self.convert("mediapipe", log)
        self.check(text, syn.mediapipe_times(), self.mediapipe_expected, special, orientation=False, default=(0.9, 0.9))
        self.assertIn("# floor: at y = 0", text)

    def test_mediapipe_mirrored_selfie(self):
        log = self.dir / "selfie.jsonl"
        special = syn.mediapipe_jsonl(log, mirrored=True)
        special = {i: (c[1], c[0]) for i, c in special.items()}  # the visibilities travel with the wrists
        special[60] = (0.9, 0.3)
        text = self.convert("mediapipe", log, mirrored=True)
        self.check(text, syn.mediapipe_times(), self.mediapipe_expected, special, orientation=False, default=(0.9, 0.9))
        # Unmirrored, the hands come out exchanged and reflected.
        _, rows = read_csv(self.convert("mediapipe", log))
        self.assertGreater(math.dist(rows[0][1:4], syn.mediapipe_expected("left", 0.0)), 0.1)

    def test_mediapipe_floor_calibrate(self):
        log = self.dir / "pose.jsonl"
        syn.mediapipe_jsonl(log)
        text = self.convert("mediapipe", log, floor="calibrate")
        _, rows = read_csv(text)
        self.assertAlmostEqual(rows[0][2], syn.wrist("left", 0.0)[1] - syn.body(0.0)[1], delta=MM)  # hips at 0
        self.assertIn("--floor calibrate", text)

    # --- malformed logs: errors name the file and line ---

    def assertFails(self, source, content, line, pattern, suffix=".log", **options):
        log = self.dir / f"bad{suffix}"
        log.write_text(content)
        with self.assertRaises(ConvertError) as caught:
            cli.convert(source, [str(log)], **options)
        message = str(caught.exception)
        prefix = f"{log}:{line}: " if line else f"{log}: "
        self.assertTrue(message.startswith(prefix), f"{message!r} should start with {prefix!r}")
        self.assertRegex(message, pattern)

    POSE_HEADER = "time_ns,hand,flags,px,py,pz,qx,qy,qz,qw\n"
    GOOD_ROW = "{t},left,15,0.1,1.0,0.2,0,0,0,1\n"

    def test_malformed_pose_rows(self):
        h, row = self.POSE_HEADER, self.GOOD_ROW
        self.assertFails("openxr", "time,hand,px,py,pz,qx,qy,qz,qw\n", 1, "lacks time_ns, flags")
        self.assertFails("openxr", h + row.format(t=5) + "6,left,15,nan,1,0,0,0,0,1\n", 3, "px is nan")
        self.assertFails("openxr", h + row.format(t=5) + row.format(t=4), 3, "does not increase")
        self.assertFails("openxr", h + row.format(t=5) + "6,lft,15,0,1,0,0,0,0,1\n", 3, "unknown hand \"lft\"")
        self.assertFails("openxr", h + row.format(t=5) + row.format(t=5), 3, "second left sample.*line 2")
        self.assertFails("openxr", h + "5,left,15,0.1,1.0,0.2,10,20,30,1\n", 2, "not a unit quaternion")
        self.assertFails("openxr", h + "5,left,15,0.1,1.0\n", 2, "expected 10 fields")
        self.assertFails("openxr", h + "5,left,x,0,1,0,0,0,0,1\n", 2, "flags is not a number")
        self.assertFails("openxr", h, 0, "no samples")
        self.assertFails("unity", "time,hand,tracked,px,py,pz,qx,qy,qz,qw\n1.0,left,yes,0,1,0,0,0,0,1\n", 2,
                         "tracked should be 1/0")
        self.assertFails("unity", "time,hand,tracked,px,py,pz,qx,qy,qz,qw\n1.0,left,1,0,5,1,0,0,0,0,1\n", 2,
                         "decimal comma")
        self.assertFails("unreal", "time,hand,tracked,px,py,pz,qx,qy,qz,qw\n1.0,right,1,0,100,,0,0,0,1\n", 2,
                         "pz is not a number")

    def test_malformed_webxr(self):
        pose = '{"handedness": "left", "position": {"x": 0, "y": 1, "z": 0}, "orientation": {"x": 0, "y": 0, "z": 0, "w": 1}}'
        self.assertFails("webxr", '{"time": 1, "poses": [' + pose + ']}\n{"time": 2, "poses": [\n', 2, "not a JSON object")
        self.assertFails("webxr", '{"poses": []}\n', 1, "missing field \"time\"")
        self.assertFails("webxr", '{"time": 1, "poses": [' + pose.replace('"left"', '"up"') + ']}\n', 1,
                         "unknown poses\\[0\\].handedness \"up\"")
        self.assertFails("webxr", '{"time": 1, "poses": [' + pose.replace('"y": 1, ', '') + ']}\n', 1,
                         "missing field \"y\"")
        self.assertFails("webxr", '{"time": 2, "poses": []}\n{"time": 1, "poses": []}\n', 2, "does not increase")
        self.assertFails("webxr", '{"time": 1, "poses": [' + pose + ', ' + pose + ']}\n', 1, "two left input sources")

    def test_malformed_arkit(self):
        identity = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0.1, 1.2, -0.3, 1]
        row_major = [1, 0, 0, 0.1, 0, 1, 0, 1.2, 0, 0, 1, -0.3, 0, 0, 0, 1]
        record = '{{"time": {t}, "hand": "{h}", "tracking": "{s}", "transform": {m}}}\n'
        good = record.format(t=1, h="left", s="normal", m=identity)
        self.assertFails("arkit", record.format(t=1, h="left", s="normal", m=row_major), 1, "column after column")
        self.assertFails("arkit", good + record.format(t=2, h="left", s="relocalizing", m=identity), 2,
                         "unknown tracking state")
        self.assertFails("arkit", good + record.format(t=2, h="left", s="normal", m=identity[:15]), 2, "16 numbers")
        self.assertFails("arkit", good + record.format(t=2, h="left", s="normal", m=[2] + identity[1:]), 2,
                         "not a rotation")
        self.assertFails("arkit", good.replace('"hand": "left", ', ''), 1, "missing field \"hand\"")
        self.assertFails("arkit", good, 0, "no right hand's samples")
        self.assertFails("arkit", good + record.format(t=900, h="right", s="normal", m=identity), 0, "one clock")

    def test_malformed_mediapipe(self):
        landmarks = [[0, 0, 0, 1]] * 33
        self.assertFails("mediapipe", '{"timestamp_ms": 0, "pose_world_landmarks": %s}\n' % ([[0, 0, 0]] * 21), 1,
                         "found 21 .*hand")
        good = '{"timestamp_ms": %d, "pose_world_landmarks": %s}\n'
        self.assertFails("mediapipe", good % (5, landmarks) + good % (5, landmarks), 2, "does not increase")
        self.assertFails("mediapipe", good % (5, [[0, 0, 0, 0.1]] * 33), 0, "no frame shows the feet.*--floor calibrate")
        self.assertFails("mediapipe", good % (5, json.dumps([[0, "a", 0, 1]] * 33)), 1, "pose_world_landmarks\\[0\\]\\[1\\]")

    def test_device_offset_longer_than_a_hand(self):
        log = self.dir / "unreal.csv"
        syn.engine_csv(log, OFFSET, syn.UNREAL, syn.unreal_quaternion)
        with self.assertRaisesRegex(ConvertError, "at most 0.5 m"):
            cli.convert("unreal", [str(log)], device_offset=(0.0, 0.0, 60.0))  # 60 cm

    # --- the command line ---

    def run_converter(self, *args):
        return subprocess.run([sys.executable, str(CONVERTER), *map(str, args)], capture_output=True, text=True,
                              timeout=60)

    def test_command_line(self):
        log, out = self.dir / "unity.csv", self.dir / "wrists.csv"
        syn.engine_csv(log, (0, 0, 0), syn.UNITY, syn.unity_quaternion)
        done = self.run_converter("unity", log, "-o", out)
        self.assertEqual(done.returncode, 0, done.stderr)
        self.assertIn("next: mocap reconstruct --database DATABASE --csv", done.stderr)
        self.assertEqual(len(read_csv(out.read_text())[1]), syn.FRAMES)

        bad = self.dir / "bad.csv"
        bad.write_text("time,hand,tracked,px,py,pz,qx,qy,qz,qw\n1,left,1,0,1,0,0,0,0,1\n0.5,left,1,0,1,0,0,0,0,1\n")
        done = self.run_converter("unity", bad, "-o", self.dir / "never.csv")
        self.assertEqual(done.returncode, 1)
        self.assertTrue(done.stderr.startswith(f"error: {bad}:3: time 0.5 does not increase"), done.stderr)
        self.assertNotIn("Traceback", done.stderr)
        self.assertFalse((self.dir / "never.csv").exists())

        done = self.run_converter("openxr", log, log, "-o", out)
        self.assertEqual(done.returncode, 1)
        self.assertIn("openxr takes one log; 2 given", done.stderr)

    # --- the CSV the product reads ---

    def test_header_is_the_documented_one(self):
        """The columns are docs/getting-started.md's spec (the header line of its CSV section)."""
        text = (ROOT / "docs" / "getting-started.md").read_text(encoding="utf-8")
        spec = re.search(r"^time,left_x,left_y,left_z,right_x,right_y,right_z\[.*\]\]$", text, re.M).group(0)
        names = re.sub(r"[\[\]]", "", spec).split(",")
        log = self.dir / "unity.csv"
        syn.engine_csv(log, (0, 0, 0), syn.UNITY, syn.unity_quaternion)
        self.assertEqual(read_csv(self.convert("unity", log))[0], names)
        mp = self.dir / "pose.jsonl"
        syn.mediapipe_jsonl(mp)
        self.assertEqual(read_csv(self.convert("mediapipe", mp))[0], names[:9])

    def test_mocap_reads_every_converted_csv(self):
        mocap = os.environ.get("MOCAP_CLI")
        if not mocap:
            self.skipTest("MOCAP_CLI (build/client/mocap) not given: the product's CSV reader is not run")
        self.assertTrue(os.access(mocap, os.X_OK), f"MOCAP_CLI={mocap} is not a program")
        files = {}
        for source, make in (("openxr", lambda p: syn.openxr_csv(p, OFFSET)),
                             ("webxr", lambda p: syn.webxr_jsonl(p, OFFSET)),
                             ("unity", lambda p: syn.engine_csv(p, OFFSET, syn.UNITY, syn.unity_quaternion)),
                             ("unreal", lambda p: syn.engine_csv(p, OFFSET, syn.UNREAL, syn.unreal_quaternion)),
                             ("mediapipe", syn.mediapipe_jsonl)):
            log = self.dir / f"{source}.log"
            make(log)
            files[source] = self.dir / f"{source}_wrists.csv"
            files[source].write_text(cli.convert(source, [str(log)])[0])
        left, right = self.dir / "left.jsonl", self.dir / "right.jsonl"
        syn.write_jsonl(left, syn.arkit_records("left", OFFSET, 0.0))
        syn.write_jsonl(right, syn.arkit_records("right", OFFSET, 0.007))
        files["arkit"] = self.dir / "arkit_wrists.csv"
        files["arkit"].write_text(cli.convert("arkit", [str(left), str(right)])[0])
        # The control: a CSV the reader refuses (one column short) must be told apart.
        files["control"] = self.dir / "control.csv"
        files["control"].write_text(files["unity"].read_text().replace(",right_qz\n", "\n", 1))

        with socket.socket() as s:  # a port nothing listens on
            s.bind(("127.0.0.1", 0))
            port = s.getsockname()[1]
        runs = {name: subprocess.Popen(
            [mocap, "--address", f"127.0.0.1:{port}", "--key", "none", "--timeout", "10", "reconstruct",
             "--database", "none", "--csv", str(path), "--unary", "--quiet", "-o", str(self.dir / name)],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) for name, path in files.items()}
        for name, run in runs.items():
            _, stderr = run.communicate(timeout=60)
            self.assertEqual(run.returncode, 1, stderr)
            if name == "control":
                self.assertIn(f"{files[name]}:", stderr, "the reader should refuse the control CSV")
                continue
            self.assertNotIn(str(files[name]), stderr, f"mocap refused the {name} CSV: {stderr}")
            self.assertRegex(stderr, "(?i)connect", f"{name}: expected only the connection to fail: {stderr}")


class DeviceDocsTest(unittest.TestCase):
    """docs/devices: a page per source, linked from the index; every relative link resolves
    (as tests/check_docs.sh also checks, for every guide)."""

    def anchors(self, path):
        found, seen = set(), {}
        fenced = False
        for line in path.read_text(encoding="utf-8").splitlines():
            if line.startswith("```"):
                fenced = not fenced
            if fenced or not re.match(r"#{1,6} ", line):
                continue
            text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", re.sub(r"^#+ ", "", line.strip()))
            slug = re.sub(r"[^\w\- ]", "", text.lower()).replace(" ", "-")
            n = seen.get(slug, 0)
            seen[slug] = n + 1
            found.add(slug if n == 0 else f"{slug}-{n}")
        return found

    def test_pages_and_links(self):
        folder = ROOT / "docs" / "devices"
        index = (folder / "README.md").read_text(encoding="utf-8")
        for source in cli.SOURCES:
            self.assertTrue((folder / f"{source}.md").exists(), source)
            self.assertIn(f"({source}.md)", index)
        for page in sorted(folder.glob("*.md")):
            text = re.sub(r"```.*?```", "", page.read_text(encoding="utf-8"), flags=re.S)
            for target in re.findall(r"\]\(([^)\s]+)\)", text):
                if re.match(r"[a-z]+:", target):
                    continue
                path, _, fragment = target.partition("#")
                file = (page.parent / path).resolve() if path else page
                self.assertTrue(file.exists(), f"{page.name}: {target}")
                if fragment:
                    self.assertIn(fragment, self.anchors(file), f"{page.name}: {target}")


if __name__ == "__main__":
    unittest.main()

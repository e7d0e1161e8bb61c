#!/usr/bin/env python3
"""Every command of README.md and docs/**/*.md runs in a test (issue #27).

Takes every command of the docs' ```sh / ```bash / ```console blocks and `$ ` lines (continuation
lines joined, comments dropped), and decides with tests/docs/doc_commands.txt how each is covered:
run here, covered by another test or script (checked to be there), or not run, with the reason.
Fails when a command matches no entry (a newly documented command cannot go untested silently), an
entry matches no command (stale), or a command run here fails. doc_commands.txt says how commands
are run: a scratch copy of the repository's layout with synthetic clips and logs, no shared data.

usage: check_doc_commands.py SOURCE_DIR [BUILD_DIR] [--only TEXT] [--keep] [--verbose]
  without BUILD_DIR: only the extraction and the mapping are checked (nothing runs)
  --only TEXT: run only the commands containing TEXT (the mapping is still checked in full)
  --keep (or MOCAP_KEEP_TEST_DIR=1): keep the scratch folder
"""
import argparse
import importlib.util
import json
import os
import re
import select
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.dont_write_bytecode = True  # the helpers it imports from tests/ and tools/ leave no __pycache__
SHELL_LANGUAGES = {"sh", "bash", "shell"}
PROGRAM_DIRS = ("mocapd", "client", "eval")  # build/DIR: mocapd; mocap, mocap-load; mocap-eval


# ---------------------------------------------------------------- extraction

def strip_comment(line):
    """The line without its shell comment (a # at a word start, outside quotes)."""
    quote = None
    i = 0
    while i < len(line):
        c = line[i]
        if quote:
            if c == "\\" and quote == '"':
                i += 1
            elif c == quote:
                quote = None
        elif c == "\\":
            i += 1
        elif c in "'\"":
            quote = c
        elif c == "#" and (i == 0 or line[i - 1].isspace()):
            return line[:i]
        i += 1
    return line


def extract(path, name):
    """[(name, line, command)] of one Markdown file."""
    commands, fence, language, pending = [], None, None, None
    for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        stripped = line.strip()
        if fence is None:
            m = re.match(r"(`{3,}|~{3,})\s*([\w+-]*)", stripped)
            if m:
                fence, language = m.group(1), m.group(2).lower()
            continue
        if stripped.startswith(fence) and stripped.strip(fence[0]) == "":
            if pending:
                raise SystemExit(f"{name}:{pending[0]}: a continued line ends its block")
            fence = None
            continue
        if pending is None:
            if stripped.startswith("$ "):
                stripped = stripped[2:]
            elif language not in SHELL_LANGUAGES:
                continue  # console output, or another language: only `$ ` lines are commands
        elif language not in SHELL_LANGUAGES and stripped.startswith("> "):
            stripped = stripped[2:]
        text = strip_comment(stripped).rstrip()
        continued = text.endswith("\\")
        if continued:
            text = text[:-1]
        start = pending[0] if pending else number
        text = (pending[1] + " " + text) if pending else text
        if continued:
            pending = (start, text)
            continue
        pending = None
        text = " ".join(text.split())
        if text:
            commands.append((name, start, text))
    return commands


def documented_commands(source):
    files = [source / "README.md"] + sorted((source / "docs").rglob("*.md"))
    commands = []
    for path in files:
        commands += extract(path, path.relative_to(source).as_posix())
    return commands


# ---------------------------------------------------------------- the mapping

class Entry:
    def __init__(self, kind, pattern, line):
        self.kind, self.line = kind, line
        self.patterns = []  # [(pattern, regex, line)]: the first, then each `or:`
        self.add(pattern, line)
        self.notes = {}
        self.forms = []  # `as:` the forms to run instead of the synopsis' own
        self.matched = {}  # pattern -> [(file, line, command)]
        self.last_note = None  # the note an indented line without a key continues

    def add(self, pattern, line):
        pattern = " ".join(pattern.split())
        regex = re.compile("".join(".*" if c == "*" else re.escape(c) for c in pattern))
        self.patterns.append((pattern, regex, line))

    def match(self, text):
        return next((p for p, regex, _ in self.patterns if regex.fullmatch(text)), None)


def read_mapping(path):
    entries, subs, problems = [], {}, []
    for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        if not line.strip() or line.startswith("#"):
            continue
        m = re.match(r"(run|covered|not-run|sub):\s*(.*)$", line)
        if m and m.group(1) == "sub":
            key, _, value = m.group(2).partition(" = ")
            subs[" ".join(key.split())] = value.strip()
        elif m:
            entries.append(Entry(m.group(1), m.group(2), number))
        elif line[:1].isspace() and entries:
            key, _, value = line.strip().partition(":")
            if key == "as":
                entries[-1].forms.append(value.strip())
                entries[-1].last_note = None
            elif key == "or":
                entries[-1].add(value, number)
                entries[-1].last_note = None
            elif key in ("by", "why", "needs"):
                entries[-1].notes[key] = value.strip()
                entries[-1].last_note = key
            elif entries[-1].last_note:  # a note continued on the next line
                entries[-1].notes[entries[-1].last_note] += " " + line.strip()
            else:
                problems.append(f"{path.name}:{number}: what is this line of an entry? {line.strip()}")
        else:
            problems.append(f"{path.name}:{number}: not an entry: {line}")
    for e in entries:
        if e.kind != "run" and any("*" in p for p, _, _ in e.patterns):
            problems.append(f"{path.name}:{e.line}: {e.kind}: patterns are whole commands (no *), so that a new "
                            "command is never taken for one covered elsewhere or not run")
        if e.kind == "covered" and not re.fullmatch(r'\S+ ".+"', e.notes.get("by", "")):
            problems.append(f'{path.name}:{e.line}: covered: needs `by: FILE "TEXT"`')
        if e.kind == "not-run" and not e.notes.get("why"):
            problems.append(f"{path.name}:{e.line}: not-run: needs `why:`")
    return entries, subs, problems


def classify(commands, entries, source):
    problems = []
    decided = []
    for name, line, text in commands:
        entry = next((e for e in entries if e.match(text)), None)
        if entry is None:
            problems.append(f"{name}:{line}: no entry in tests/docs/doc_commands.txt covers: {text}")
            continue
        entry.matched.setdefault(entry.match(text), []).append((name, line, text))
        decided.append((name, line, text, entry))
    for e in entries:
        for pattern, _, number in e.patterns:
            if pattern not in e.matched:
                problems.append(f"doc_commands.txt:{number}: stale: no documented command matches `{e.kind}: {pattern}`")
        if e.kind == "covered":
            file, text = re.fullmatch(r'(\S+) "(.+)"', e.notes["by"]).groups()
            target = source / file
            if not target.is_file():
                problems.append(f"doc_commands.txt:{e.line}: covered by {file}, which does not exist")
            elif text not in target.read_text(encoding="utf-8"):
                problems.append(f'doc_commands.txt:{e.line}: covered by {file}, which no longer contains "{text}"')
    return decided, problems


# ---------------------------------------------------------------- synopsis forms

class Group:
    def __init__(self, opening):
        self.opening, self.alternatives = opening, [[]]


def parse(text):
    """The command as a tree: strings and Groups ([optional] or (required), each with its
    alternatives). A `|` inside a group separates alternatives unless it is inside a word right
    after an option (`--layout overlay|side-by-side`: that option's values)."""
    root = []
    stack = [(None, root)]  # (group, current sequence)
    word, previous, quote = "", "", None

    def emit(c):
        seq = stack[-1][1]
        if seq and isinstance(seq[-1], str):
            seq[-1] += c
        else:
            seq.append(c)

    for c in text:
        if quote:
            emit(c)
            word += c
            if c == quote:
                quote = None
        elif c in "'\"":
            quote = c
            emit(c)
            word += c
        elif c in "[(" and not word.endswith("$"):
            group = Group(c)
            stack[-1][1].append(group)
            stack.append((group, group.alternatives[0]))
            word, previous = "", ""
        elif c in "])" and len(stack) > 1 and stack[-1][0].opening == {"]": "[", ")": "("}[c]:
            stack.pop()
            word, previous = "", "]"
        elif c == "|" and len(stack) > 1 and not (word and previous.startswith("-")):
            group = stack[-1][0]
            group.alternatives.append([])
            stack[-1] = (group, group.alternatives[-1])
            word, previous = "", ""
        elif c.isspace():
            if word:
                previous, word = word, ""
            emit(c)
        else:
            emit(c)
            word += c
    if len(stack) != 1 or quote:
        raise ValueError(f"unbalanced brackets or quotes: {text}")
    return root


def groups_of(seq):
    for node in seq:
        if isinstance(node, Group):
            yield node
            for alternative in node.alternatives:
                yield from groups_of(alternative)


def render(seq, choose):
    out = []
    for node in seq:
        if isinstance(node, str):
            out.append(node)
        else:
            choice = choose(node)
            if choice is not None:
                out.append(" " + render(node.alternatives[choice], choose) + " ")
    return "".join(out)


def forms(text):
    """Every form of a synopsis: none of the optional parts, all of them (first choices), and
    each other choice of each group (with all of its own optional parts, none of the others'). A
    plain command is its only form."""
    tree = parse(text)
    groups = list(groups_of(tree))
    least = lambda g: None if g.opening == "[" else 0  # noqa: E731
    choosers = [least, lambda g: 0]
    for group in groups:
        for i in range(1, len(group.alternatives)):
            inside = set(map(id, groups_of(group.alternatives[i])))
            choosers.append(lambda g, group=group, i=i, inside=inside:
                            i if g is group else 0 if id(g) in inside else least(g))
    result = []
    for choose in choosers:
        words = [w for w in render(tree, choose).split() if w != "..."]
        form = " ".join(words)
        if form not in result:
            result.append(form)
    return result


def split_words(text):
    """Words separated by spaces outside quotes, quotes kept."""
    words, word, quote = [], "", None
    for c in text:
        if quote:
            word += c
            if c == quote:
                quote = None
        elif c in "'\"":
            quote = c
            word += c
        elif c.isspace():
            if word:
                words.append(word)
            word = ""
        else:
            word += c
    if word:
        words.append(word)
    return words


def substitute(text, subs):
    words = split_words(text)
    out = []
    for i, word in enumerate(words):
        previous = words[i - 1] if i else ""
        base = word[:-3] if word.endswith("...") and len(word) > 3 else word
        for key in (f"{previous} {word}", f"{previous} {base}", word, base):
            if key in subs:
                word = subs[key]
                break
        else:
            word = base
            if "|" in word and word != "|" and word[0] not in "'\"":
                word = word.split("|")[0]  # an option's values: the first
        out.append(word)
    return " ".join(out)


# ---------------------------------------------------------------- the scratch layout

def load_module(path, name):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


# The other rig: the synthetic walk's joints renamed (CMU-like) and its lengths in metres.
OTHER_RIG_NAMES = {
    "Hips": "hip", "Spine": "abdomen", "Chest": "chest", "Neck": "neck", "Head": "head",
    "LeftShoulder": "lCollar", "LeftArm": "lShldr", "LeftForeArm": "lForeArm", "LeftHand": "lHand",
    "RightShoulder": "rCollar", "RightArm": "rShldr", "RightForeArm": "rForeArm", "RightHand": "rHand",
    "LeftUpLeg": "lThigh", "LeftLeg": "lShin", "LeftFoot": "lFoot", "LeftToeBase": "lToe",
    "RightUpLeg": "rThigh", "RightLeg": "rShin", "RightFoot": "rFoot", "RightToeBase": "rToe",
}


def other_rig(plain_bvh, out):
    lines, motion = [], False
    for line in plain_bvh.read_text().splitlines():
        m = re.match(r"(\s*)(ROOT|JOINT) (\S+)$", line)
        if m:
            line = f"{m.group(1)}{m.group(2)} {OTHER_RIG_NAMES[m.group(3)]}"
        elif re.match(r"\s*OFFSET ", line):
            indent, _, values = line.partition("OFFSET ")
            line = indent + "OFFSET " + " ".join(f"{float(v) / 100:.6f}" for v in values.split())
        elif line.startswith("Frame Time:"):
            motion = True
        elif motion and line.strip():
            values = line.split()
            values[:3] = [f"{float(v) / 100:.6f}" for v in values[:3]]
            line = " ".join(values)
        lines.append(line)
    out.write_text("\n".join(lines) + "\n")


def query_pose(walk_module, out):
    """One pose as named joint positions (the rest pose of the synthetic rig, cm, Y up)."""
    joints, _ = walk_module.build_body()
    world, listed = [], []
    for name, parent, offset, _ in joints:
        base = world[parent] if parent >= 0 else [0.0, 0.0, 0.0]
        world.append([base[i] + offset[i] for i in range(3)])
        listed.append({"name": name, "parent": joints[parent][0] if parent >= 0 else None,
                       "position": world[-1]})
    out.write_text(json.dumps({"up": "+Y", "joints": listed, "landmarks": {
        "pelvis": "Hips", "head": "Head", "left_wrist": "LeftHand", "right_wrist": "RightHand",
        "left_ankle": "LeftFoot", "right_ankle": "RightFoot"}}, indent=1) + "\n")


class Layout:
    """The scratch folder: fixture/ made once, a fresh copy of it per docs file."""

    def __init__(self, source, build, root):
        self.source, self.build, self.root = source, build, root
        self.walk = load_module(source / "tests" / "deploy" / "synthetic_walk.py", "synthetic_walk")
        sys.path.insert(0, str(source / "tests" / "tools" / "converters"))
        sys.path.insert(0, str(source / "tools" / "converters"))
        self.syn = load_module(source / "tests" / "tools" / "converters" / "synthetic.py", "synthetic")
        from mocapconv import cli  # noqa: E402  (tools/converters)
        self.convert = cli.convert
        self.missing = {}  # file name -> why the layout has none
        self.key = None

    def program(self, name):
        directory = {"mocapd": "mocapd", "mocap": "client", "mocap-load": "client", "mocap-eval": "eval"}[name]
        return str(self.build / directory / name)

    def bvh(self, path, frames, cycle=1.0, speed=120.0, start=0.0):
        path.parent.mkdir(parents=True, exist_ok=True)
        self.walk.write_bvh(str(path), self.walk.Walk(cycle, speed), frames, start)

    def run(self, *args, **kwargs):
        done = subprocess.run(args, capture_output=True, text=True, timeout=120, **kwargs)
        if done.returncode != 0:
            raise SystemExit(f"layout: {' '.join(map(str, args))} failed ({done.returncode}):\n{done.stderr[-2000:]}")
        return done.stdout

    def make_fixture(self):
        d = self.root / "fixture"
        home = d / "home"
        # Synthetic walks: ~/captures (the database `walks`), a stand-in of the shared data.
        for i, (frames, cycle, speed) in enumerate(((90, 1.0, 120), (120, 1.1, 115), (150, 0.95, 125)), 1):
            self.bvh(home / "captures" / f"walk_0{i}.bvh", frames, cycle, speed)
        data = home / ".cache" / "mocap" / "data"
        for take, (frames, cycle, speed, start) in {1: (120, 1.0, 122, 0), 2: (150, 1.08, 112, 0.2),
                                                    3: (120, 1.02, 118, 0.3), 4: (150, 0.97, 126, 0.1)}.items():
            self.bvh(data / "bandai-namco-2" / f"dataset-2_walk_normal_00{take}.bvh", frames, cycle, speed, start)
        plain = d / "plain.bvh"
        self.bvh(plain, 240, 1.05, 117, 0.4)
        (data / "cmu-cc").mkdir(parents=True)
        other_rig(plain, data / "cmu-cc" / "002_01.bvh")
        self.bvh(plain, 100, 0.98, 121, 0.1)
        other_rig(plain, d / "AVATAR.bvh")
        plain.unlink()
        # The files the docs name.
        self.bvh(d / "FILE.bvh", 100, 1.02, 119, 0.5)
        self.bvh(d / "CLIP.bvh", 100, 1.03, 118, 0.2)
        self.bvh(d / "walk.bvh", 90, 0.99, 123, 0.6)
        query_pose(self.walk, d / "POSE.json")
        self.walk.write_csv(str(d / "wrists.csv"), self.walk.Walk(1.02, 118), 60, 0.3)
        rows = (d / "wrists.csv").read_text().splitlines()
        (d / "wrists_cm.csv").write_text("\n".join([rows[0]] + [
            ",".join([r.split(",")[0]] + [f"{float(v) * 100:.4f}" for v in r.split(",")[1:]]) for r in rows[1:]]) + "\n")
        extra = ",left_confidence,right_confidence,left_qw,left_qx,left_qy,left_qz,right_qw,right_qx,right_qy,right_qz"
        (d / "WRISTS.csv").write_text("\n".join([rows[0] + extra] + [r + ",1,1,1,0,0,0,1,0,0,0" for r in rows[1:]]) + "\n")
        log = d / "openxr_controllers.log"
        self.syn.openxr_csv(log, (0.0, 0.0, 0.1))
        (d / "controllers.csv").write_text(self.convert("openxr", [str(log)])[0])
        log.unlink()
        if shutil.which("openssl"):
            self.run("openssl", "req", "-x509", "-newkey", "rsa:2048", "-nodes", "-days", "1", "-subj", "/CN=localhost",
                     "-addext", "subjectAltName=IP:127.0.0.1,DNS:localhost", "-keyout", d / "KEY.pem", "-out", d / "CERT.pem")
        else:
            self.missing["CERT.pem"] = self.missing["KEY.pem"] = "no openssl to make a test certificate"
        # The store: walks, bandai-namco-2 (the standard split's way: takes not ≡ 3 mod 10), others.
        store = d / "var" / "mocap.db"
        store.parent.mkdir()
        mocapd = self.program("mocapd")
        self.run(mocapd, "import", "--store", store, "--database", "walks", "--quiet", home / "captures")
        self.run(mocapd, "import", "--store", store, "--database", "bandai-namco-2", "--quiet",
                 *sorted(p for p in (data / "bandai-namco-2").glob("*.bvh") if not p.name.endswith("3.bvh")))
        self.run(mocapd, "import", "--store", store, "--database", "others", "--quiet", data / "cmu-cc" / "002_01.bvh")
        self.key = self.run(mocapd, "tenant", "add-key", "--store", store, "default").strip()
        # Reconstructions: MORE.bvh + MORE.json (a BVH with its traces), and out/stream/ as the
        # quick start leaves it.
        server = Server(mocapd, store, d / "server.log")
        try:
            mocap = self.program("mocap")
            for database, clip, output in (("walks", d / "CLIP.bvh", d / "MORE"),
                                           ("bandai-namco-2", data / "bandai-namco-2" / "dataset-2_walk_normal_003.bvh",
                                            d / "out" / "stream" / "dataset-2_walk_normal_003"),
                                           ("walks", d / "FILE.bvh", d / "out" / "stream" / "file")):
                output.parent.mkdir(parents=True, exist_ok=True)
                self.run(mocap, "--address", server.address, "--key", self.key, "reconstruct", "--database", database,
                         "--bvh", clip, "--noise-cm", "0.5", "--seed", "1", "--lag", "5", "--quiet", "-o", output)
        finally:
            server.stop()
        (d / "server.log").unlink()
        return d

    def device_logs(self, doc, d):
        """The logs the device pages convert, under the names they use."""
        syn, offset = self.syn, (0.01, -0.02, 0.09)
        page = Path(doc).name
        if page == "arkit.md" or doc == "docs/devices/README.md":
            syn.write_jsonl(d / "left.jsonl", syn.arkit_records("left", offset, 0.0))
            syn.write_jsonl(d / "right.jsonl", syn.arkit_records("right", offset, 0.007))
            both = [dict(r, hand=hand) for hand, start in (("left", 0.0), ("right", 0.007))
                    for r in syn.arkit_records(hand, offset, start)]
            syn.write_jsonl(d / "both.jsonl", sorted(both, key=lambda r: r["time"]))
        elif page == "mediapipe.md":
            syn.mediapipe_jsonl(d / "pose.jsonl")
        elif page == "openxr.md":
            syn.openxr_csv(d / "hands.csv", (0.0, 0.0, 0.0))
            syn.openxr_csv(d / "controllers.csv", offset)
        elif page == "unity.md":
            syn.engine_csv(d / "wrists.csv", offset, syn.UNITY, syn.unity_quaternion)
        elif page == "unreal.md":
            syn.engine_csv(d / "wrists.csv", offset, syn.UNREAL, syn.unreal_quaternion)
        if page == "webxr.md" or doc == "docs/devices/README.md":
            syn.webxr_jsonl(d / "session.jsonl", offset)

    def for_doc(self, fixture, doc):
        d = self.root / re.sub(r"[^\w.-]", "_", doc)
        shutil.copytree(fixture, d, symlinks=True)
        (d / "build").symlink_to(self.build)
        for name in ("tools", "client"):
            (d / name).symlink_to(self.source / name)
        if doc == "docs/getting-started.md":  # its own commands fill the store
            shutil.rmtree(d / "var")
            (d / "var").mkdir()
        self.device_logs(doc, d)
        return d


class Server:
    """`mocapd serve` on a free loopback port (the scratch one, or a documented serve command)."""

    def __init__(self, command_or_mocapd, store=None, log=None, cwd=None, env=None, shell=False):
        if shell:
            args = ["bash", "-c", "exec " + command_or_mocapd]
        else:
            args = [command_or_mocapd, "serve", "--store", str(store), "--listen", "127.0.0.1:0", "--drain-seconds", "1"]
        self.log = open(log, "w") if log else subprocess.PIPE
        self.process = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=self.log, cwd=cwd, env=env,
                                        text=True, start_new_session=True)
        self.address, self.output = None, ""
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:
            ready, _, _ = select.select([self.process.stdout], [], [], 0.2)
            if ready:
                line = self.process.stdout.readline()
                self.output += line
                m = re.match(r"listening on (\S+)", line)
                if m:
                    self.address = m.group(1)
                    return
                if not line:
                    break
            elif self.process.poll() is not None:
                break
        self.stop()
        raise RuntimeError(f"mocapd serve printed no 'listening on' within 30 s: {' '.join(args)}\n{self.errors()}")

    def errors(self):
        if self.log is subprocess.PIPE:
            return ""
        return Path(self.log.name).read_text()[-2000:] if Path(self.log.name).exists() else ""

    def stop(self):
        """SIGTERM; its exit code (SIGKILL after 15 s: None)."""
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGTERM)
            try:
                self.process.wait(timeout=15)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
                return None
        if self.log is not subprocess.PIPE:
            self.log.close()
        return self.process.returncode


# ---------------------------------------------------------------- running

class DocRun:
    """The commands of one docs file, in order, in its own scratch folder."""

    def __init__(self, layout, fixture, doc, subs):
        self.layout, self.doc, self.subs = layout, doc, subs
        self.dir = layout.for_doc(fixture, doc)
        home = self.dir / "home"
        path = ":".join(str(layout.build / p) for p in PROGRAM_DIRS)
        self.env = {"HOME": str(home), "PATH": f"{path}:/usr/local/bin:/usr/bin:/bin", "LANG": "C.UTF-8",
                    "TMPDIR": str(self.dir), "PYTHONDONTWRITEBYTECODE": "1"}
        if doc != "docs/getting-started.md":
            self.env["MOCAP_API_KEY"] = layout.key
        self.key = layout.key if doc != "docs/getting-started.md" else None
        self.last_key = None
        self.server = None

    def close(self):
        if self.server:
            self.server.stop()

    def values(self):
        address = self.server.address if self.server else "{address}"
        return {"address": address, "key": self.key or "{key}",
                "last_key_id": self.last_key[:11] if self.last_key else "{last_key_id}"}

    def ensure_server(self):
        if self.server is None:
            self.server = Server(self.layout.program("mocapd"), self.dir / "var" / "mocap.db", self.dir / "scratch-server.log")
            self.env["MOCAP_ADDRESS"] = self.server.address

    def prepare(self, form):
        text = substitute(form, self.subs)
        needs_server = "{address}" in text or (re.search(r"(^|[\s/])mocap(-load)?\s", text)
                                                and not re.search(r"(^|[\s/])mocap\s+view\s", text))
        if needs_server:
            self.ensure_server()
        for name, value in self.values().items():
            if "{" + name + "}" in text and value.startswith("{"):
                raise RuntimeError(f"no value for {{{name}}} here (a key must be made first)")
            text = text.replace("{" + name + "}", value)
        return text

    def outputs(self, words):
        """The files a command says it writes."""
        expected = []
        reconstruct = "reconstruct" in words
        for i, word in enumerate(words[:-1]):
            value = words[i + 1]
            if word in ("-o", "--output"):
                expected += [value + ".bvh", value + ".json"] if reconstruct else [value]
            elif word == "--out":
                expected.append(value)
        expected += [w.split("=", 1)[1] for w in words if w.startswith("--screenshot=")]
        return expected

    def run(self, form, entry):
        """(status, message): status 'ok', 'skip' or 'fail'."""
        status, message = self.run_form(form, entry)
        if status == "fail" and self.server:
            log = Path(self.server.log.name).read_text(errors="replace").splitlines()[-15:]
            message += "\n----- the scratch server's log (last lines)\n" + "\n".join(log)
        return status, message

    def run_form(self, form, entry):
        needs = entry.notes.get("needs")
        if needs and not shutil.which(needs, path=self.env["PATH"]):
            return "skip", f"{needs} is not installed"
        if "[OPTIONS]" in split_words(form):
            return self.run_help(form, split_words(form))
        try:
            text = self.prepare(form)
        except RuntimeError as e:
            return "fail", str(e)
        words = split_words(text)
        for word in words:
            if word in self.layout.missing:
                return "skip", self.layout.missing[word]
        if len(words) >= 2 and Path(words[0]).name == "mocapd" and words[1] == "serve":
            return self.run_serve(text)
        m = re.fullmatch(r"export (\w+)=(\S+)", text)
        if m:
            done = self.shell(f'export {m.group(1)}={m.group(2)}; printf %s "${m.group(1)}"')
            if done.returncode == 0:
                self.env[m.group(1)] = done.stdout
            return self.verdict(text, done, [])
        done = self.shell("set -o pipefail; " + text)
        for line in done.stdout.splitlines():
            if re.fullmatch(r"mk_[0-9a-f]{8}_\w+", line.strip()):
                self.last_key = line.strip()
                if re.search(r"add-key( --store \S+)? default\b", text):
                    self.key = self.last_key
        return self.verdict(text, done, self.outputs(words))

    def shell(self, script, timeout=180):
        process = subprocess.Popen(["bash", "-c", script], cwd=self.dir, env=self.env, stdout=subprocess.PIPE,
                                   stderr=subprocess.PIPE, text=True, start_new_session=True)
        try:
            stdout, stderr = process.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGKILL)
            stdout, stderr = process.communicate()
            stderr += f"\n(killed after {timeout} s)"
        return subprocess.CompletedProcess(process.args, process.returncode, stdout, stderr)

    def verdict(self, text, done, outputs):
        if done.returncode != 0:
            return "fail", f"exit code {done.returncode}: {text}\n{(done.stdout + done.stderr)[-3000:]}"
        missing = [o for o in outputs if not (self.dir / o).exists()]
        if missing:
            return "fail", f"exit code 0 but no {', '.join(missing)}: {text}"
        return "ok", text

    def run_help(self, text, words):
        program = words[:words.index("[OPTIONS]")]
        done = self.shell(" ".join(program + ["--help"]))
        if done.returncode != 0:
            return self.verdict(text, done, [])
        usage = next((line for line in done.stdout.splitlines() if line.startswith("Usage: ")), None)
        if usage != "Usage: " + text:
            return "fail", f"`{' '.join(program)} --help` says `{usage}`, the docs `{text}`"
        return "ok", " ".join(program + ["--help"])

    def run_serve(self, text):
        if "--listen" not in split_words(text):
            text += " --listen 127.0.0.1:0"  # never the default port 50051 of a shared machine
        try:
            server = Server(text, cwd=self.dir, env=self.env, log=self.dir / "documented-serve.log", shell=True)
        except RuntimeError as e:
            return "fail", f"{text}\n{e}"
        code = server.stop()
        if code != 0:
            return "fail", f"{text}: listened on {server.address}, then exited {code} on SIGTERM\n{server.errors()}"
        return "ok", f"{text} (listened on {server.address}, stopped by SIGTERM)"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("source", type=Path)
    parser.add_argument("build", type=Path, nargs="?")
    parser.add_argument("--only")
    parser.add_argument("--keep", action="store_true")
    parser.add_argument("--verbose", action="store_true")
    args = parser.parse_args()
    source = args.source.resolve()
    started = time.monotonic()

    commands = documented_commands(source)
    entries, subs, problems = read_mapping(source / "tests" / "docs" / "doc_commands.txt")
    decided, more = classify(commands, entries, source)
    problems += more
    counts = {kind: sum(1 for *_, e in decided if e.kind == kind) for kind in ("run", "covered", "not-run")}
    distinct = len({text for _, _, text in commands})
    print(f"{len(commands)} documented commands ({distinct} distinct) in README.md and docs/: "
          f"{counts['run']} run here, {counts['covered']} covered by other tests or scripts, "
          f"{counts['not-run']} not run (doc_commands.txt says why)")
    for e in entries:
        if e.kind == "not-run":
            print("\n".join(f"  not run: {p}" for p, _, _ in e.patterns) + f"\n    why: {e.notes['why']}")
    if problems:
        print("\n".join(["FAIL:"] + problems))
        return 1
    if args.build is None:
        return 0

    build = args.build.resolve()
    for name, directory in (("mocapd", "mocapd"), ("mocap", "client"), ("mocap-load", "client"), ("mocap-eval", "eval")):
        if not os.access(build / directory / name, os.X_OK):
            print(f"FAIL: {build / directory / name} is not built")
            return 1
    root = Path(tempfile.mkdtemp(prefix="mocap-doc-commands."))
    results = {"ok": 0, "skip": 0, "fail": 0}
    failures = []
    try:
        layout = Layout(source, build, root)
        fixture = layout.make_fixture()
        print(f"scratch layout made in {time.monotonic() - started:.1f} s ({root})")
        by_doc = {}
        for name, line, text, entry in decided:
            if entry.kind == "run" and (not args.only or args.only in text):
                by_doc.setdefault(name, []).append((line, text, entry))
        for doc, items in by_doc.items():
            doc_started = time.monotonic()
            run = DocRun(layout, fixture, doc, subs)
            try:
                for line, text, entry in items:
                    try:
                        these = entry.forms or (forms(text) if "[OPTIONS]" not in text else [text])
                    except ValueError as e:
                        these = []
                        results["fail"] += 1
                        failures.append(f"{doc}:{line}: {e}")
                        print(f"  FAIL {doc}:{line}: {e}")
                    for form in these:
                        status, message = run.run(form, entry)
                        results[status] += 1
                        if status == "fail":
                            failures.append(f"{doc}:{line}: {message}")
                            print(f"  FAIL {doc}:{line}: {message}")
                        elif status == "skip" or args.verbose:
                            print(f"  {status.upper()} {doc}:{line}: {message}")
            finally:
                run.close()
            print(f"{doc}: {len(items)} commands in {time.monotonic() - doc_started:.1f} s")
    finally:
        if args.keep or os.environ.get("MOCAP_KEEP_TEST_DIR") == "1":
            print(f"kept {root}")
        else:
            shutil.rmtree(root, ignore_errors=True)
    print(f"ran {sum(results.values())} command forms: {results['ok']} passed, {results['skip']} skipped, "
          f"{results['fail']} failed ({time.monotonic() - started:.1f} s)")
    if failures:
        print("FAIL: these documented commands failed (tests/docs/doc_commands.txt says how they are run):")
        print("\n".join("  " + f.splitlines()[0] for f in failures))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())

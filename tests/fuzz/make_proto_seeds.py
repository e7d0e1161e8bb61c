"""Seeds for the fuzz targets that read protobuf messages made from real files (tests/fuzz/run.sh
encodes the text-format files written here with protoc):
  target_rig_fuzz           a TargetRig per BVH file, in both forms: its text, and its hierarchy as
                            joints (name, parent, offset, end site; the unit left to detection);
  pose_search_request_fuzz  a FindSimilarPosesRequest per BVH file (a few of its frames as the
                            query) and per pose JSON file (the pose as named joints).
usage: make_proto_seeds.py OUT_DIR BVH... -- POSE_JSON...
"""
import json
import pathlib
import sys


def quoted(text):
    """A protobuf text-format string literal (ASCII escapes only)."""
    out = []
    for ch in text:
        code = ord(ch)
        if ch in '"\\':
            out.append("\\" + ch)
        elif ch == "\n":
            out.append("\\n")
        elif ch == "\r":
            out.append("\\r")
        elif ch == "\t":
            out.append("\\t")
        elif 32 <= code < 127:
            out.append(ch)
        else:
            out.extend("\\%03o" % b for b in ch.encode("utf-8"))
    return '"' + "".join(out) + '"'


def vec3(values):
    return "{ x: %s y: %s z: %s }" % tuple(repr(float(v)) for v in values)


def hierarchy_joints(text):
    """(name, parent index, offset, end site) of each joint of a BVH hierarchy, parents first."""
    tokens = text.split("MOTION")[0].split()
    joints, stack, i, in_end_site = [], [], 0, False
    while i < len(tokens):
        token = tokens[i]
        if token in ("ROOT", "JOINT"):
            joints.append([tokens[i + 1], stack[-1] if stack else -1, None, None])
            i += 2
        elif token == "End":
            in_end_site = True
            i += 2
        elif token == "{":
            stack.append(len(joints) - 1 if not in_end_site else stack[-1])
            i += 1
        elif token == "}":
            stack.pop()
            in_end_site = False
            i += 1
        elif token == "OFFSET":
            offset = [float(v) for v in tokens[i + 1:i + 4]]
            if in_end_site:
                joints[stack[-1]][3] = offset
            else:
                joints[-1][2] = offset
            i += 4
        else:
            i += 1
    return joints


def main():
    out = pathlib.Path(sys.argv[1])
    split = sys.argv.index("--")
    bvh_files, pose_files = sys.argv[2:split], sys.argv[split + 1:]
    rigs, searches = out / "target_rig_fuzz", out / "pose_search_request_fuzz"
    rigs.mkdir(parents=True, exist_ok=True)
    searches.mkdir(parents=True, exist_ok=True)
    for path in map(pathlib.Path, bvh_files):
        text = path.read_text(errors="replace")
        (rigs / (path.stem + "_bvh.txtpb")).write_text("bvh: %s\n" % quoted(text))
        lines = []
        for name, parent, offset, end_site in hierarchy_joints(text):
            line = "joints { name: %s parent: %d offset: %s" % (quoted(name), parent, vec3(offset or [0, 0, 0]))
            if end_site:
                line += " end_site: %s" % vec3(end_site)
            lines.append(line + " }")
        (rigs / (path.stem + "_joints.txtpb")).write_text("joints {\n  %s\n}\n" % "\n  ".join(lines))
        (searches / (path.stem + ".txtpb")).write_text(
            'databases: "walks"\nbvh { bvh: %s file_name: %s first_frame: 0 last_frame: 6 frame_step: 3 }\n'
            "top_k: 3\nwindow: 3\n" % (quoted(text), quoted(path.name)))
    for path in map(pathlib.Path, pose_files):
        pose = json.loads(path.read_text())
        joints = "\n".join(
            "  joints { name: %s parent: %s position: %s }" % (quoted(j["name"]), quoted(j.get("parent") or ""),
                                                                 vec3(j["position"])) for j in pose["joints"])
        landmarks = " ".join("%s: %s" % (k, quoted(v)) for k, v in pose.get("landmarks", {}).items())
        (searches / (path.stem + "_pose.txtpb")).write_text(
            'databases: "walks"\nposes { poses {\n%s\n  up: %s\n  landmarks { %s }\n} }\ntop_k: 5\n'
            % (joints, quoted(pose.get("up", "")), landmarks))


if __name__ == "__main__":
    main()

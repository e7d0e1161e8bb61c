#!/usr/bin/env python3
"""A large target rig for the fairness flood (benchmarks/fairness_flood.sh): the hierarchy of a
BVH file with N extra zero-length leaf joints under its head (as a rig with facial helper bones
has), and the file's first frame (the extra joints' channels 0). Each session that retargets onto it analyses all of its joints at setup.

usage: make_big_rig.py SOURCE.bvh N > big.bvh
"""
import re
import sys


def main() -> None:
    source, extra = sys.argv[1], int(sys.argv[2])
    text = open(source).read()
    hierarchy = text[: text.index("MOTION")]
    # The head's End Site becomes N leaf joints, each with its own End Site.
    match = re.search(r"(JOINT Head\s*\{.*?)(End Site\s*\{[^}]*\})", hierarchy, re.S)
    if not match:
        sys.exit(f"{source}: no joint named Head with an End Site")
    leaves = "\n".join(
        f"JOINT face_{i}\n{{\nOFFSET 0.0 {0.001 * (i % 10):.3f} 0.0\n"
        "CHANNELS 3 Zrotation Xrotation Yrotation\nEnd Site\n{\nOFFSET 0.0 0.001 0.0\n}\n}"
        for i in range(extra)
    )
    before = sum(int(n) for n in re.findall(r"CHANNELS\s+(\d+)", hierarchy[: match.start(2)]))
    hierarchy = hierarchy[: match.start(2)] + leaves + hierarchy[match.end(2):]
    motion = text[text.index("MOTION"):].splitlines()
    frame_time = next(line for line in motion if line.startswith("Frame Time"))
    first = next(line for line in motion[1:] if line.strip() and not line.startswith("Frame")).split()
    values = first[:before] + ["0"] * (3 * extra) + first[before:]
    sys.stdout.write(hierarchy)
    sys.stdout.write(f"MOTION\nFrames: 1\n{frame_time}\n{' '.join(values)}\n")


if __name__ == "__main__":
    main()

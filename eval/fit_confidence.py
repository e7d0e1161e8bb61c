#!/usr/bin/env python3
"""Fits the landmark confidence calibration (docs/method.md "Confidence",
motion/reconstruct/landmark_confidence.cc) on development data only:

  - the development split (mocap-eval --dev-split: the database holds the test performers' styles);
  - the same test takes with their style left out of the database (leave one style out, seven
    databases), the regime of a body the database lacks.

Each regime's (frame, landmark) pairs weigh alike. Model, per landmark k:
  log e_k = a_k + b_d log(d + 1e-4) + b_w log(w + 1e-4) + b_c log(c + 1e-3) + b_s S
by least squares on log(error + 1e-3); then a_k += log mean exp(residual) (the mean, not the
median, is predicted). Prints the constants to paste and how well they do in each regime.

Usage: eval/fit_confidence.py [--mocap-eval build/eval/mocap-eval] [--work DIR]
Needs python3-numpy and the shared data (bandai-namco-2 unpacked where mocap-eval finds it).
"""
import argparse
import csv
import os
import pathlib
import subprocess
import sys

import numpy as np

LANDMARKS = ["pelvis", "head", "left_shoulder", "right_shoulder", "left_elbow", "right_elbow", "left_wrist",
             "right_wrist", "left_hip", "right_hip", "left_knee", "right_knee", "left_ankle", "right_ankle"]
STYLES = ["active", "elderly", "exhausted", "feminine", "masculine", "normal", "youthful"]
CUES = ["distance", "wrist_fit_m", "solver_cost", "session_log_cost"]


def run(cmd):
    print("+", " ".join(str(c) for c in cmd), file=sys.stderr)
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)


def leave_style_out_sets(data, work):
    """Per style: a database of the other styles' takes not ≡ 3 or 5 (mod 10) and the style's takes ≡ 5."""
    sets = []
    for style in STYLES:
        db, test = work / style / "db", work / style / "test"
        for folder in (db, test):
            folder.mkdir(parents=True, exist_ok=True)
            for link in folder.iterdir():
                link.unlink()
        for bvh in sorted(data.glob("dataset-2_*.bvh")):
            parts = bvh.stem.split("_")
            take = int(parts[-1]) % 10
            if parts[2] == style:
                if take == 5:
                    (test / bvh.name).symlink_to(bvh)
            elif take not in (3, 5):
                (db / bvh.name).symlink_to(bvh)
        sets.append((style, db, test))
    return sets


def load(path):
    rows = list(csv.DictReader(open(path)))
    landmark = np.array([LANDMARKS.index(r["landmark"]) for r in rows])
    actual = np.array([float(r["actual_m"]) for r in rows])
    cues = {c: np.array([float(r[c]) for r in rows]) for c in CUES}
    return landmark, actual, cues


def design(landmark, cues):
    columns = [(landmark == k).astype(float) for k in range(len(LANDMARKS))]
    columns += [np.log(cues["distance"] + 1e-4), np.log(cues["wrist_fit_m"] + 1e-4),
                np.log(cues["solver_cost"] + 1e-3), cues["session_log_cost"]]
    return np.stack(columns, 1)


def spearman(a, b):
    ra, rb = np.argsort(np.argsort(a)), np.argsort(np.argsort(b))
    return float(np.corrcoef(ra, rb)[0, 1])


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--mocap-eval", default="build/eval/mocap-eval")
    parser.add_argument("--work", default="/tmp/mocap-confidence-fit")
    parser.add_argument("--data", default=os.path.expanduser("~/.cache/mocap/data/bandai-namco-2"),
                        help="the unpacked bandai-namco-2 folder")
    args = parser.parse_args()
    work = pathlib.Path(args.work)
    work.mkdir(parents=True, exist_ok=True)
    common = [args.mocap_eval, "--runs", "full", "--no-bvh"]
    run(common + ["--dev-split", "--out", work / "dev", "--confidence-samples", work / "dev.csv"])
    regimes = {"development split": [work / "dev.csv"], "style left out": []}
    for style, db, test in leave_style_out_sets(pathlib.Path(args.data), work):
        out = work / f"{style}.csv"
        run(common + ["--database-dir", db, "--test", test, "--out", work / f"out-{style}", "--confidence-samples", out])
        regimes["style left out"].append(out)

    data = {}
    for name, files in regimes.items():
        parts = [load(f) for f in files]
        data[name] = (np.concatenate([p[0] for p in parts]), np.concatenate([p[1] for p in parts]),
                      {c: np.concatenate([p[2][c] for p in parts]) for c in CUES})
    x = np.concatenate([design(l, c) for l, _, c in data.values()])
    y = np.log(np.concatenate([a for _, a, _ in data.values()]) + 1e-3)
    weight = np.concatenate([np.full(len(a), 1.0 / len(a)) for _, a, _ in data.values()])
    root = np.sqrt(weight)
    beta = np.linalg.lstsq(x * root[:, None], y * root, rcond=None)[0]
    residual = np.exp(y - x @ beta)
    landmark = np.concatenate([l for l, _, _ in data.values()])
    for k in range(len(LANDMARKS)):
        beta[k] += np.log(np.average(residual[landmark == k], weights=weight[landmark == k]))
    print("kLogBase =", ", ".join(f"{b:.4f}f" for b in beta[:len(LANDMARKS)]))
    for name, b in zip(["kDistanceExponent", "kWristFitExponent", "kCostExponent", "kSessionCostExponent"],
                       beta[len(LANDMARKS):]):
        print(f"{name} = {b:.4f}f")
    for name, (l, actual, cues) in data.items():
        predicted = np.exp(design(l, cues) @ beta)
        order = np.argsort(predicted)
        bins = [actual[b].mean() / predicted[b].mean() for b in np.array_split(order, 10)]
        print(f"{name}: Spearman {spearman(predicted, actual):.3f}; actual / predicted per bin "
              + " ".join(f"{r:.2f}" for r in bins))


if __name__ == "__main__":
    main()

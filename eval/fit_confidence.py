#!/usr/bin/env python3
"""Fits the landmark confidence calibration (docs/method.md "Confidence",
motion/reconstruct/landmark_confidence.cc) on development data only, in two stages.

Tracked landmarks, on two regimes weighted alike:
  - the development split (mocap-eval --dev-split: the database holds the test performers' styles);
  - the same test takes with their style left out of the database (leave one style out, seven
    databases), the regime of a body the database lacks.
  Model, per landmark k:
    log e_k = a_k + b_d log(d + 1e-4) + b_w log(w + 1e-4) + b_c log(c + 1e-3) + b_s S
  by least squares on log(error + 1e-3); then a_k += log mean exp(residual) (the mean, not the
  median, is predicted).

Landmarks whose input is not real (untracked seconds u > 0: a dropout bridged by interpolation,
or a hand lost while the other is tracked), on the development split's takes streamed with
dropouts (mocap-eval --devices: one dropout of 0.5, 1, 2 or 5 s, dropouts of 0.1-2 s every 4 s,
the left hand alone lost for 1, 2 or 5 s). There the cues of the solve say little (the body meets
an input that is a guess), so they have a model of their own:
    log e_k = a'_k + b_u log(1 + u / 0.1 s)
fitted the same way. Prints the constants to paste and how well they do in each regime.

--other-sizes F ... adds a third tracked regime, weighted alike: the development split with every
performer F times the database's (mocap-eval --test-body-scale F). Tried at stop 83 with 0.9 1.1 and
not kept (docs/evaluation.md): the cues do not see a body's size, so the regime only raises every
prediction.

Usage: eval/fit_confidence.py [--mocap-eval build/eval/mocap-eval] [--work DIR] [--no-run] [--check FILE ...]
                              [--other-sizes F ...]
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
SIDELESS_NAMES = ["pelvis", "head", "shoulder", "elbow", "wrist", "hip", "knee", "ankle"]
SIDELESS = np.array([0, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7])  # LANDMARKS → SIDELESS_NAMES
STYLES = ["active", "elderly", "exhausted", "feminine", "masculine", "normal", "youthful"]
CUES = ["distance", "wrist_fit_m", "solver_cost", "session_log_cost", "untracked_s"]
DROPOUT_RUNS = ["full@dropout_0.5s", "full@dropout_1s", "full@dropout_2s", "full@dropout_5s", "full@dropouts",
                "full@left_hand_lost_1s", "full@left_hand_lost_2s", "full@left_hand_lost_5s"]
UNTRACKED_SCALE_S = 0.1


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
    parser.add_argument("--no-run", action="store_true", help="refit the samples an earlier run left in --work")
    parser.add_argument("--check", nargs="*", default=[], type=pathlib.Path,
                        help="--confidence-samples files of other runs (the standard split, the cross-dataset protocol) "
                             "to report the new constants on: measured there, never fitted")
    parser.add_argument("--other-sizes", nargs="*", default=[], type=float, metavar="F",
                        help="also fit the development split with every performer F times the database's size")
    args = parser.parse_args()
    work = pathlib.Path(args.work)
    work.mkdir(parents=True, exist_ok=True)
    common = [args.mocap_eval, "--runs", "full", "--no-bvh"]
    execute = (lambda cmd: None) if args.no_run else run
    execute(common + ["--dev-split", "--out", work / "dev", "--confidence-samples", work / "dev.csv"])
    execute(common[:1] + ["--dev-split", "--landmarks", "--devices", "--no-bvh", "--runs", "full"] + DROPOUT_RUNS +
        ["--out", work / "dropouts", "--confidence-samples", work / "dropouts.csv"])
    for scale in args.other_sizes:
        execute(common + ["--dev-split", "--landmarks", "--test-body-scale", str(scale), "--out", work / f"dev-{scale}",
                          "--confidence-samples", work / f"dev-{scale}.csv"])
    regimes = {"development split": [work / "dev.csv"], "style left out": [],
               "dropouts": [work / f"dropouts.{name}.csv" for name in DROPOUT_RUNS]}
    for style, db, test in leave_style_out_sets(pathlib.Path(args.data), work):
        out = work / f"{style}.csv"
        execute(common + ["--database-dir", db, "--test", test, "--out", work / f"out-{style}", "--confidence-samples", out])
        regimes["style left out"].append(out)
    if args.other_sizes:
        regimes["other sizes"] = [work / f"dev-{scale}.csv" for scale in args.other_sizes]

    data = {}
    for name, files in regimes.items():
        parts = [load(f) for f in files]
        data[name] = (np.concatenate([p[0] for p in parts]), np.concatenate([p[1] for p in parts]),
                      {c: np.concatenate([p[2][c] for p in parts]) for c in CUES})
    tracked_regimes = [data[name] for name in ("development split", "style left out", "other sizes") if name in data]
    beta = fit([design(l, c) for l, _, c in tracked_regimes], [a for _, a, _ in tracked_regimes],
               [l for l, _, _ in tracked_regimes])
    l, a, c = data["dropouts"]
    untracked = c["untracked_s"] > 0
    guessed = fit([untracked_design(l[untracked], c["untracked_s"][untracked])], [a[untracked]],
                  [SIDELESS[l[untracked]]], len(SIDELESS_NAMES))
    guessed = np.concatenate([guessed[SIDELESS], guessed[len(SIDELESS_NAMES):]])  # per landmark again
    print("kLogBase =", ", ".join(f"{b:.4f}f" for b in beta[:len(LANDMARKS)]))
    for name, b in zip(["kDistanceExponent", "kWristFitExponent", "kCostExponent", "kSessionCostExponent"],
                       beta[len(LANDMARKS):]):
        print(f"{name} = {b:.4f}f")
    print("kUntrackedLogBase =", ", ".join(f"{b:.4f}f" for b in guessed[:len(LANDMARKS)]))
    print(f"kUntrackedExponent = {guessed[len(LANDMARKS)]:.4f}f")
    for name, (l, actual, cues) in data.items():
        predicted = predict(beta, guessed, l, cues)
        report(name, predicted, actual)
        untracked = cues["untracked_s"] > 0
        if untracked.any():
            report(f"  of which untracked ({untracked.sum()} pairs)", predicted[untracked], actual[untracked])
            report(f"  of which tracked ({(~untracked).sum()} pairs)", predicted[~untracked], actual[~untracked])
    for path in args.check:
        l, actual, cues = load(path)
        report(f"check {path.name}", predict(beta, guessed, l, cues), actual)


def untracked_design(landmark, untracked_s, per_landmark=False):
    """Intercepts per landmark without its side (the dropouts lose the left hand alone; either may be
    lost), or per landmark (the expanded constants)."""
    group = landmark if per_landmark else SIDELESS[landmark]
    count = len(LANDMARKS) if per_landmark else len(SIDELESS_NAMES)
    columns = [(group == k).astype(float) for k in range(count)]
    columns.append(np.log1p(untracked_s / UNTRACKED_SCALE_S))
    return np.stack(columns, 1)


def fit(designs, actuals, landmarks, intercepts=len(LANDMARKS)):
    """Least squares of log(actual + 1e-3), each regime weighted alike, then the mean correction of
    each intercept (the first `intercepts` columns; `landmarks` says each sample's)."""
    x = np.concatenate(designs)
    y = np.log(np.concatenate(actuals) + 1e-3)
    weight = np.concatenate([np.full(len(a), 1.0 / len(a)) for a in actuals])
    root = np.sqrt(weight)
    beta = np.linalg.lstsq(x * root[:, None], y * root, rcond=None)[0]
    residual = np.exp(y - x @ beta)
    landmark = np.concatenate(landmarks)
    for k in range(intercepts):
        beta[k] += np.log(np.average(residual[landmark == k], weights=weight[landmark == k]))
    return beta


def predict(beta, guessed, landmark, cues):
    """As ExpectedLandmarkErrors: the untracked model where the landmark's input is not real."""
    untracked = cues["untracked_s"] > 0
    return np.where(untracked, np.exp(untracked_design(landmark, cues["untracked_s"], True) @ guessed),
                    np.exp(design(landmark, cues) @ beta))


def report(name, predicted, actual):
    order = np.argsort(predicted)
    bins = [actual[b].mean() / predicted[b].mean() for b in np.array_split(order, 10)]
    worst = max(max(r, 1 / r) for r in bins)
    print(f"{name}: Spearman {spearman(predicted, actual):.3f}; worst bin {worst:.2f}; actual / predicted per bin "
          + " ".join(f"{r:.2f}" for r in bins))

if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Scores est.log files with the standard 3DMatch registration-recall protocol, independently
of the C++ runner (its own log/info parsing and error formula), so the two can be compared.

  /usr/bin/python3 scripts/score-3dmatch.py RESULTS_DIR [--gt ../shared/data/3dmatch-gt]

RESULTS_DIR is a `zeroreg eval 3dmatch --out` folder (it holds <benchmark>/<scene>/est.log).
Per benchmark and scene: pairs (i, j) of gt.log with j > i + 1 are evaluated; a pair is
registered iff E = xi^T Info xi / Info[0, 0] <= 0.2^2, with xi = (t, q_xyz) of
inv(T_gt) T_est (q the unit quaternion with w >= 0) and Info from gt.info. Only the pairs in
est.log are scored: a run covers the pairs of the fragments it has (redkitchen 0-19 here), and
the runner writes every pair it attempted, failed ones included. Recall is averaged over scenes. With --pairs it also prints
each pair's verdict, to compare with the runner's pairs.jsonl.
"""
import argparse
import json
import os
import sys

import numpy as np


def read_blocks(path, rows):
    """Reads a .log / .info file: a header line 'i j n' followed by `rows` matrix rows."""
    with open(path) as f:
        lines = [line.split() for line in f if line.strip()]
    out = {}
    for k in range(0, len(lines), rows + 1):
        i, j = int(lines[k][0]), int(lines[k][1])
        out[(i, j)] = np.array([[float(x) for x in lines[k + 1 + r]] for r in range(rows)])
    return out


def quaternion_xyz(R):
    """Unit quaternion (w >= 0) of a rotation matrix; returns its (x, y, z) part."""
    w = np.sqrt(max(0.0, 1.0 + R[0, 0] + R[1, 1] + R[2, 2])) / 2.0
    x = np.sqrt(max(0.0, 1.0 + R[0, 0] - R[1, 1] - R[2, 2])) / 2.0
    y = np.sqrt(max(0.0, 1.0 - R[0, 0] + R[1, 1] - R[2, 2])) / 2.0
    z = np.sqrt(max(0.0, 1.0 - R[0, 0] - R[1, 1] + R[2, 2])) / 2.0
    x = np.copysign(x, R[2, 1] - R[1, 2])
    y = np.copysign(y, R[0, 2] - R[2, 0])
    z = np.copysign(z, R[1, 0] - R[0, 1])
    return np.array([x, y, z])


def error(T_gt, T_est, info):
    D = np.linalg.inv(T_gt) @ T_est
    xi = np.concatenate([D[:3, 3], quaternion_xyz(D[:3, :3])])
    return float(xi @ info @ xi / info[0, 0])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("results")
    ap.add_argument("--gt", default=os.path.join("..", "shared", "data", "3dmatch-gt"))
    ap.add_argument("--pairs", action="store_true", help="print every pair's verdict")
    args = ap.parse_args()
    verdicts = {}
    for bench in sorted(os.listdir(args.results)):
        bench_dir = os.path.join(args.results, bench)
        if not os.path.isdir(bench_dir) or not os.path.isdir(os.path.join(args.gt, bench)):
            continue
        recalls = []
        for scene in sorted(os.listdir(bench_dir)):
            est_path = os.path.join(bench_dir, scene, "est.log")
            gt_dir = os.path.join(args.gt, bench, scene)
            if not os.path.exists(est_path):
                continue
            gt = read_blocks(os.path.join(gt_dir, "gt.log"), 4)
            info = read_blocks(os.path.join(gt_dir, "gt.info"), 6)
            est = read_blocks(est_path, 4)
            # Only the pairs the run attempted (a run may cover part of a scene's pairs).
            evaluated = [p for p in est if p in gt and p[1] > p[0] + 1]
            ok = 0
            for p in evaluated:
                registered = error(gt[p], est[p], info[p]) <= 0.04
                ok += registered
                verdicts[f"{bench}/{scene} {p[0]} {p[1]}"] = registered
            if evaluated:
                recalls.append(ok / len(evaluated))
                print(f"{bench} {scene}: {ok}/{len(evaluated)} registered")
        if recalls:
            print(f"{bench}: registration recall {100 * np.mean(recalls):.1f}% (mean over scenes)")
    if args.pairs:
        print(json.dumps(verdicts, indent=0, sort_keys=True))
    return 0


if __name__ == "__main__":
    sys.exit(main())

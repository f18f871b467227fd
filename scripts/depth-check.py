#!/usr/bin/env python3
"""Which explains the depth images better, the estimate or the ground truth? A check of the
frame-pair benchmark's ground truth, independent of any registration method.

  /usr/bin/python3 scripts/depth-check.py RESULTS_DIR [--min-error-cm 5] [--data DIR]

RESULTS_DIR is a `zeroreg eval pairs --out` folder of a 3DMatch-layout sequence (7-Scenes
redkitchen by default). For every pair whose estimate is more than --min-error-cm from the ground
truth, the source depth image is back-projected, moved by T (the ground truth, then the estimate)
and projected into the target camera; the script prints, for each T, the median |depth
difference| over the pixels that land on valid target depth within 10 cm (an ICP-style
consistency measure) and how many pixels that is. An estimate with a lower median and at least as
many consistent pixels fits the two depth images better than the ground-truth pose does: its
"error" is then at least partly the ground truth's.

Needs the zeroreg Python module (for its PNG reader): build/python, or $ZEROREG_PYTHONPATH.
"""
import argparse
import json
import os
import sys

import numpy as np

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.environ.get("ZEROREG_PYTHONPATH") or os.path.join(REPO, "build", "python"))
import zeroreg  # noqa: E402


def load_depth(data, frame):
    d = zeroreg.read_depth(os.path.join(data, "frames", f"frame-{frame:06d}.depth.png"))
    d = d.astype(np.float64)
    d[d == 65535] = 0  # 7-Scenes marks invalid depth with 0 or 65535 (MANIFEST)
    return d / 1000.0


def consistency(K, source_depth, target_depth, T, gate_m=0.10):
    v, u = np.nonzero(source_depth > 0)
    z = source_depth[v, u]
    p = np.stack([(u - K[0, 2]) * z / K[0, 0], (v - K[1, 2]) * z / K[1, 1], z], axis=1)
    q = p @ T[:3, :3].T + T[:3, 3]
    front = q[:, 2] > 0.05
    q = q[front]
    x = np.round(q[:, 0] / q[:, 2] * K[0, 0] + K[0, 2]).astype(int)
    y = np.round(q[:, 1] / q[:, 2] * K[1, 1] + K[1, 2]).astype(int)
    h, w = target_depth.shape
    inside = (x >= 0) & (x < w) & (y >= 0) & (y < h)
    measured = target_depth[y[inside], x[inside]]
    diff = np.abs(measured - q[inside, 2])[measured > 0]
    diff = diff[diff < gate_m]
    return (float(np.median(diff)) if diff.size else float("nan")), int(diff.size)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("results")
    ap.add_argument("--data", default=os.path.join("..", "shared", "data", "7scenes-redkitchen"))
    ap.add_argument("--min-error-cm", type=float, default=5.0)
    args = ap.parse_args()
    K = np.loadtxt(os.path.join(args.data, "camera-intrinsics.txt"))
    checked = better = 0
    print("source target | error deg cm | median |dz| cm, pixels: ground truth -> estimate")
    with open(os.path.join(args.results, "pairs.jsonl")) as f:
        records = [json.loads(line) for line in f]
    for r in sorted(records, key=lambda r: r["target"]):
        if r["translation_error_m"] * 100 <= args.min_error_cm:
            continue
        s, t = load_depth(args.data, r["source"]), load_depth(args.data, r["target"])
        gt = consistency(K, s, t, np.array(r["T_gt"]))
        est = consistency(K, s, t, np.array(r["T_est"]))
        wins = est[0] < gt[0] and est[1] >= gt[1]
        checked += 1
        better += wins
        print(f"{r['source']:5d} {r['target']:5d} | {r['rotation_error_deg']:5.2f} "
              f"{100 * r['translation_error_m']:5.1f} | {100 * gt[0]:.2f} {gt[1]:6d} -> "
              f"{100 * est[0]:.2f} {est[1]:6d}{'  estimate fits better' if wins else ''}")
    print(f"{checked} pairs beyond {args.min_error_cm:g} cm; on {better} of them the estimate "
          f"fits the depth images better than the ground truth")
    return 0


if __name__ == "__main__":
    sys.exit(main())

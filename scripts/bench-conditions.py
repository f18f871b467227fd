#!/usr/bin/env python3
"""Capture conditions the lists do not have: the same pairs, with one or both scans changed.

The pairs of ../shared/lists come from three sensors, each held one way, in one exposure. A user's
scans may not be: a phone gives frames in portrait or landscape (ARKit keeps the sensor's
orientation, so a session held the other way is turned by a quarter turn), a camera may be upside
down, a second session may be darker, have a shorter depth range or more holes. This script takes
--per-list pairs from every list (evenly spread over pair_stats.tsv), changes them as each
condition says, registers them with the default pipeline (one Pipeline, seed 0) and counts the
verdicts against the ground truth (right = RE < 15 deg and TE < 30 cm, the suite's criterion):

  none                nothing changed (the reference)
  source-turned-90    the source camera rolled by a quarter turn: its colour and depth images
  source-turned-180   turned clockwise by 90 / 180 / 270 deg, intrinsics to match; the camera
  source-turned-270   frame turns with them, so the ground truth does too
  source-rolled-20    the source camera rolled by 20 / 45 deg (a tilted hand): its images
  source-rolled-45    resampled (nearest pixel), size and intrinsics kept, corners left empty
  source-half-size    the source's images at half the width and height (every other pixel)
  source-darker       the source's colour at 45 % exposure and gamma 1.6
  depth-to-3m         both scans' depth cut at 3 m (a short-range sensor)
  depth-holes         both scans lose 30 % of their depth in 16 x 16 pixel blocks (seeded)

    PYTHONPATH=build/python /usr/bin/python3 scripts/bench-conditions.py \\
        [--per-list 4] [--conditions none,source-turned-90,...] [--out results/conditions] \\
        [--set section.key=value ...]

Writes OUT/pairs.jsonl (one record per pair and condition: list, frames, verdict, errors, path,
time) and OUT/summary.md, prints the summary, and exits 1 when some wrong result was reported valid.
"""
import argparse
import json
import os
import statistics
import sys
import time

import numpy as np

sys.path.insert(0, os.environ.get("ZEROREG_PYTHONPATH", "build/python"))
import zeroreg  # noqa: E402
from bench_common import parse_sets  # noqa: E402

SCENES = {"redkitchen": "7scenes-redkitchen", "hololens": "hololens-office",
          "cabinet": "tum-fr3-cabinet"}

# A camera point (X, Y, Z) seen in the image turned a quarter turn clockwise is (-Y, X, Z): turned
# pixel (x', y') shows unturned (y', h - 1 - x').
QUARTER_CLOCKWISE = np.array([[0, -1, 0, 0], [1, 0, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])


def single_camera(scan):
    """The changes below turn the camera frame itself: only for frames (one view, the scan frame
    being the camera's), which every pair of the lists is."""
    if len(scan.views) != 1 or not np.allclose(scan.views[0].T_scan_camera, np.eye(4)):
        sys.exit(f"{scan.name}: expected a single frame (one view, identity T_scan_camera)")


def turned(scan, quarter_turns):
    """The scan with its camera rolled clockwise; returns (scan, new camera from old camera)."""
    single_camera(scan)
    R = np.eye(4)
    for _ in range(quarter_turns):
        for view in scan.views:
            h = view.color.shape[0]
            view.color = np.ascontiguousarray(np.rot90(view.color, k=-1))
            view.depth = np.ascontiguousarray(np.rot90(view.depth, k=-1))
            K = np.asarray(view.intrinsics, dtype=np.float64)
            view.intrinsics = np.array([[K[1, 1], 0, h - 1 - K[1, 2]], [0, K[0, 0], K[0, 2]],
                                        [0, 0, 1.0]])
        R = QUARTER_CLOCKWISE @ R
    return scan, R


def rolled(scan, degrees):
    """The camera rolled about its axis by `degrees` (clockwise in the image), image size and
    intrinsics kept: each new pixel takes the nearest old pixel of the homography K R K^-1; the
    corners that the old image does not cover have no colour and no depth."""
    single_camera(scan)
    a = np.radians(degrees)
    R = np.eye(4)
    R[:2, :2] = [[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]]
    for view in scan.views:
        K = np.asarray(view.intrinsics, dtype=np.float64)
        h, w = view.depth.shape
        v, u = np.mgrid[0:h, 0:w]
        rays = np.linalg.inv(K) @ np.stack([u.ravel(), v.ravel(), np.ones(u.size)])
        old = K @ (R[:3, :3].T @ rays)
        x = np.round(old[0] / old[2]).astype(int).reshape(h, w)
        y = np.round(old[1] / old[2]).astype(int).reshape(h, w)
        inside = (x >= 0) & (x < w) & (y >= 0) & (y < h)
        color = np.zeros_like(view.color)
        depth = np.zeros(view.depth.shape, dtype=np.float32)
        color[inside] = view.color[y[inside], x[inside]]
        depth[inside] = np.asarray(view.depth)[y[inside], x[inside]]
        view.color, view.depth = color, depth
    return scan, R


def half_size(scan):
    for view in scan.views:
        view.color = np.ascontiguousarray(view.color[::2, ::2])
        view.depth = np.ascontiguousarray(view.depth[::2, ::2])
        K = np.array(view.intrinsics, dtype=np.float64)
        K[:2] /= 2  # new pixel x is old pixel 2x: f and c halve
        view.intrinsics = K
    return scan, np.eye(4)


def darker(scan):
    for view in scan.views:
        c = view.color.astype(np.float64) / 255.0
        view.color = np.clip(255 * 0.45 * c ** 1.6, 0, 255).astype(np.uint8)
    return scan, np.eye(4)


def depth_to_3m(scan):
    for view in scan.views:
        d = np.array(view.depth, dtype=np.float32)
        d[d > 3.0] = 0
        view.depth = d
    return scan, np.eye(4)


def depth_holes(scan, seed):
    rng = np.random.default_rng(seed)
    for view in scan.views:
        d = np.array(view.depth, dtype=np.float32)
        blocks = rng.random((d.shape[0] // 16 + 1, d.shape[1] // 16 + 1)) < 0.3
        d[np.repeat(np.repeat(blocks, 16, 0), 16, 1)[: d.shape[0], : d.shape[1]]] = 0
        view.depth = d
    return scan, np.eye(4)


def unchanged(scan):
    return scan, np.eye(4)


# condition: (change of the source, change of the target); a change returns (scan, R) with R the
# new camera frame from the old one.
CONDITIONS = {
    "none": (unchanged, unchanged),
    "source-turned-90": (lambda s: turned(s, 1), unchanged),
    "source-turned-180": (lambda s: turned(s, 2), unchanged),
    "source-turned-270": (lambda s: turned(s, 3), unchanged),
    "source-rolled-20": (lambda s: rolled(s, 20), unchanged),
    "source-rolled-45": (lambda s: rolled(s, 45), unchanged),
    "source-half-size": (half_size, unchanged),
    "source-darker": (darker, unchanged),
    "depth-to-3m": (depth_to_3m, depth_to_3m),
    "depth-holes": (lambda s: depth_holes(s, 1), lambda s: depth_holes(s, 2)),
}


def list_pairs(lists_dir, per_list):
    out = []
    for name in sorted(os.listdir(lists_dir)):
        stats = os.path.join(lists_dir, name, "pair_stats.tsv")
        scene = SCENES.get(name.split("-")[0])
        if scene is None or not os.path.exists(stats):
            continue
        with open(stats) as f:
            rows = [line.split() for line in f][1:]
        for k in np.unique(np.linspace(0, len(rows) - 1, per_list).round().astype(int)):
            out.append((name, scene, int(rows[k][0]), int(rows[k][1])))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", default="../shared/data")
    ap.add_argument("--lists", default="../shared/lists")
    ap.add_argument("--per-list", type=int, default=4, help="pairs per list, evenly spread")
    ap.add_argument("--conditions", default=",".join(CONDITIONS),
                    help=f"comma-separated, of: {', '.join(CONDITIONS)}")
    ap.add_argument("--out", default="results/conditions")
    ap.add_argument("--set", action="append", default=[], help="config override section.key=value")
    args = ap.parse_args()
    conditions = [c for c in args.conditions.split(",") if c]
    for c in conditions:
        if c not in CONDITIONS:
            sys.exit(f"--conditions: unknown condition {c!r}; expected some of {list(CONDITIONS)}")
    if args.per_list < 1:
        sys.exit(f"--per-list {args.per_list}: expected at least 1")
    pairs = list_pairs(args.lists, args.per_list)
    if not pairs:
        sys.exit(f"{args.lists}: no list with a pair_stats.tsv of a known scene ({list(SCENES)})")
    os.makedirs(args.out, exist_ok=True)
    pipeline = zeroreg.Pipeline(parse_sets(args.set), seed=0)

    records = []
    with open(os.path.join(args.out, "pairs.jsonl"), "w") as out:
        for condition in conditions:
            change_source, change_target = CONDITIONS[condition]
            for n, (name, scene, i, j) in enumerate(pairs):
                target = zeroreg.load_scan(f"{os.path.join(args.data, scene)}@{i}")
                source = zeroreg.load_scan(f"{os.path.join(args.data, scene)}@{j}")
                gt = np.linalg.inv(target.T_world_scan_gt) @ source.T_world_scan_gt
                source, R_source = change_source(source)
                target, R_target = change_target(target)
                gt = R_target @ gt @ np.linalg.inv(R_source)
                start = time.perf_counter()
                r = pipeline.register(source, target)
                seconds = time.perf_counter() - start
                re = zeroreg.rotation_error_deg(r.T_target_source, gt)
                te = zeroreg.translation_error_m(r.T_target_source, gt)
                rec = {"condition": condition, "list": name, "target": i, "source": j,
                       "valid": bool(r.valid), "right": bool(re < 15 and te < 0.3),
                       "rotation_error_deg": re, "translation_error_m": te, "path": r.path,
                       "reason": r.reason, "time_ms": round(1000 * seconds, 1)}
                records.append(rec)
                out.write(json.dumps(rec) + "\n")
                out.flush()
                print(f"[{condition} {n + 1}/{len(pairs)}] {name} {i} <- {j}: "
                      f"{'valid' if r.valid else 'invalid'}, {'right' if rec['right'] else 'wrong'}"
                      f" ({re:.1f} deg, {100 * te:.1f} cm, {r.path})", file=sys.stderr, flush=True)

    lines = ["| condition | pairs | right (%) | valid-right / valid-WRONG / invalid-right / "
             "invalid-wrong | median ms / pair |", "|---|---|---|---|---|"]
    for condition in conditions:
        recs = [r for r in records if r["condition"] == condition]
        count = {(v, ri): 0 for v in (True, False) for ri in (True, False)}
        for r in recs:
            count[(r["valid"], r["right"])] += 1
        right = 100.0 * sum(r["right"] for r in recs) / len(recs)
        lines.append(f"| {condition} | {len(recs)} | {right:.1f} | {count[(True, True)]} / "
                     f"{count[(True, False)]} / {count[(False, True)]} / {count[(False, False)]} | "
                     f"{statistics.median(r['time_ms'] for r in recs):.0f} |")
    for rec in records:
        if not rec["right"]:
            lines.append(f"\n{'VALID-WRONG' if rec['valid'] else 'wrong, invalid'}: "
                         f"{rec['condition']} {rec['list']} {rec['target']} <- {rec['source']} "
                         f"({rec['rotation_error_deg']:.1f} deg, "
                         f"{100 * rec['translation_error_m']:.1f} cm, {rec['path']})")
    summary = "\n".join(lines) + "\n"
    with open(os.path.join(args.out, "summary.md"), "w") as f:
        f.write(summary)
    print(summary)
    return 1 if any(r["valid"] and not r["right"] for r in records) else 0


if __name__ == "__main__":
    sys.exit(main())

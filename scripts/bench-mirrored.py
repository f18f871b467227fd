#!/usr/bin/env python3
"""A left-right mirrored frame registered against the original: none may be valid (a benchmark).

No rigid motion maps a scan onto its mirror image, so every result reported valid here is a wrong
answer reported valid. For each of three lists of ../shared/lists (one per scene), --per-list pairs
(i, j) spread evenly over the list are taken; the source frame j is mirrored left-right (colour and
depth images flipped, the intrinsics kept: a user's flipped frame) and registered against the
original target frame i. The same pairs unmirrored are registered as well (--no-original skips
them): they must stay valid, or the refusal of the mirrored ones says nothing.

    PYTHONPATH=build/python /usr/bin/python3 scripts/bench-mirrored.py \
        [--per-list 9] [--out results/mirrored] [--set section.key=value ...]

Writes OUT/pairs.jsonl (one record per registration: list, frames, mirrored or not, valid, path,
verification fields, reason) and OUT/summary.md, prints the summary and exits 1 when a mirrored
frame was registered valid. The pipeline is the default one (or the --set overrides), seed 0.
"""
import argparse
import json
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.environ.get("ZEROREG_PYTHONPATH", "build/python"))
import zeroreg  # noqa: E402
from bench_common import parse_sets  # noqa: E402

LISTS = [("cabinet-gap1", "tum-fr3-cabinet"), ("redkitchen-gap20", "7scenes-redkitchen"),
         ("hololens-gap1", "hololens-office")]


def read_pairs(path):
    pairs = []
    with open(path) as f:
        for line in f:
            if line.strip() and not line.startswith("#"):
                i, j = line.split()[:2]
                pairs.append((int(i), int(j)))
    return pairs


def view_dict(view, mirrored):
    """One view of a loaded scan as the dict the Python API takes; flipped left-right if asked."""
    color, depth = np.asarray(view.color), np.asarray(view.depth)
    if mirrored:
        color, depth = color[:, ::-1], depth[:, ::-1]
    out = {"color": np.ascontiguousarray(color), "depth": np.ascontiguousarray(depth),
           "intrinsics": np.asarray(view.intrinsics)}
    if view.depth_scale:
        out["depth_scale"] = view.depth_scale
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", default="../shared/data")
    ap.add_argument("--lists", default="../shared/lists")
    ap.add_argument("--per-list", type=int, default=9, help="pairs per list (spread evenly)")
    ap.add_argument("--out", default="results/mirrored")
    ap.add_argument("--no-original", action="store_true", help="skip the unmirrored pairs")
    ap.add_argument("--set", action="append", default=[], help="config override section.key=value")
    args = ap.parse_args()
    if args.per_list < 1:
        sys.exit(f"--per-list {args.per_list}: expected a positive number of pairs")
    for name, scene in LISTS:
        for path in (os.path.join(args.lists, name, "pairs.txt"),
                     os.path.join(args.data, scene, "frames")):
            if not os.path.exists(path):
                sys.exit(f"{path}: not found (--lists / --data hold the lists {LISTS})")
    os.makedirs(args.out, exist_ok=True)
    pipeline = zeroreg.Pipeline(parse_sets(args.set), seed=0)

    records = []
    with open(os.path.join(args.out, "pairs.jsonl"), "w") as out:
        for name, scene in LISTS:
            pairs = read_pairs(os.path.join(args.lists, name, "pairs.txt"))
            step = max(1, len(pairs) // args.per_list)
            for i, j in pairs[::step][:args.per_list]:
                target_scan = zeroreg.load_scan(f"{os.path.join(args.data, scene)}@{i}")
                source_scan = zeroreg.load_scan(f"{os.path.join(args.data, scene)}@{j}")
                target = {"views": [view_dict(v, False) for v in target_scan.views]}
                kinds = [True] if args.no_original else [False, True]
                for mirrored in kinds:
                    source = {"views": [view_dict(v, mirrored) for v in source_scan.views]}
                    start = time.perf_counter()
                    r = pipeline.register(source, target).to_dict()
                    v = r.get("verification") or {}
                    rec = {"list": name, "scene": scene, "target": i, "source": j,
                           "mirrored": mirrored, "valid": bool(r["valid"]), "path": r["path"],
                           "T_est": np.asarray(r["T_target_source"]).tolist(),
                           "inliers": r["counts"].get("inliers"),
                           "correspondences": r["counts"].get("correspondences"),
                           "refusal": r.get("refusal"),
                           "verification": {k: v.get(k) for k in (
                               "overlap", "violation", "residual_rms_m", "score",
                               "brightness_rank_correlation", "probe_contradicted",
                               "degenerate", "descriptor_agreement", "covisible_keypoints")},
                           "reason": r["reason"],
                           "time_ms": round(1000 * (time.perf_counter() - start), 1)}
                    records.append(rec)
                    out.write(json.dumps(rec) + "\n")
                    out.flush()
                    print(f"{name} {i} {j} {'mirrored' if mirrored else 'original'}: "
                          f"{'VALID' if rec['valid'] else 'invalid'} ({rec['path']})", flush=True)

    lines = ["| list | mirrored valid (must be 0) | originals valid |", "|---|---|---|"]
    for name, _ in LISTS:
        mir = [r for r in records if r["list"] == name and r["mirrored"]]
        org = [r for r in records if r["list"] == name and not r["mirrored"]]
        org_text = f"{sum(r['valid'] for r in org)} of {len(org)}" if org else "not run"
        lines.append(f"| {name} | {sum(r['valid'] for r in mir)} of {len(mir)} | {org_text} |")
    mir = [r for r in records if r["mirrored"]]
    bad = sum(r["valid"] for r in mir)
    lines.append(f"| all | {bad} of {len(mir)} | "
                 f"{sum(r['valid'] for r in records if not r['mirrored'])} of "
                 f"{sum(not r['mirrored'] for r in records)} |")
    text = "\n".join(lines) + "\n"
    with open(os.path.join(args.out, "summary.md"), "w") as f:
        f.write(text)
    print(text)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())

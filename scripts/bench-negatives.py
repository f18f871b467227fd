#!/usr/bin/env python3
"""Pairs that do not overlap, or barely: no wrong result may be valid (a benchmark, not a test).

A loop-closure front end asks zeroreg about many candidate pairs, and most of them do not show
the same surfaces at all. The frame lists of ../shared/lists hold only overlapping pairs, so
they cannot show whether the pipeline refuses the rest. This script registers two kinds of pairs
that share nothing and counts the results reported valid (every one is a valid-but-wrong
result: no transform makes two scans without common surfaces agree):

  same scene   frames of one scene of ../shared/data whose ground-truth co-visibility is below
               --max-covisibility in both directions (depth of one frame moved into the other
               camera by the ground truth, within 10 cm of the depth measured there: the rule of
               ../shared/lists/README.md); candidates drawn at random (fixed seed) from the
               scene's frames, the first --per-scene that qualify are kept
  cross scene  a frame of one scene against a frame of another (different rooms, sensors)
  low overlap  frames of one scene whose co-visibility (the smaller direction) lies in
               --low-band (default 2-15 %): the regime where a wrong pose can look as good as
               the right one; a valid result there must be right (RE < 15 deg, TE < 30 cm)

    PYTHONPATH=build/python /usr/bin/python3 scripts/bench-negatives.py \
        [--per-scene 30] [--cross 30] [--low-overlap 30] [--out results/negatives] \
        [--prior-error DEG M [--prior-tolerance DEG M]] [--set section.key=value ...]

--prior-error registers every pair with a motion prior (zeroreg MotionPrior): for pairs of one
scene the ground truth moved by DEG about a random axis and M metres in a random direction
(seeded), as an odometry guess of that error would be; for cross-scene pairs, which have no truth,
the identity moved the same way (a loop-closure candidate from another room, the guess being
"the same place"): ICP from it must not make them valid.

Writes OUT/pairs.jsonl (one record per pair: kind, scenes, frames, co-visibility, valid, errors
against the ground truth where there is one, path, reason, time) and OUT/summary.md, prints the
summary, and exits 1 when some wrong result was reported valid. The pipeline is the default one (or
the --set overrides), seed 0, one Pipeline for all pairs.
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
from bench_common import parse_sets, pose_off_by  # noqa: E402

SCENES = ["7scenes-redkitchen", "hololens-office", "tum-fr3-cabinet"]


def frame_ids(scene_dir):
    ids = []
    for name in os.listdir(os.path.join(scene_dir, "frames")):
        if name.endswith(".pose.txt"):
            ids.append(int(name.split(".")[0].split("-")[1]))
    return sorted(ids)


def camera_points(view, stride=4):
    """Valid depth pixels of a view on a grid, as camera-frame points (metres)."""
    depth = np.asarray(view.depth, dtype=np.float64)
    if view.depth_scale:
        depth = depth / view.depth_scale
    K = np.asarray(view.intrinsics)
    v, u = np.mgrid[0 : depth.shape[0] : stride, 0 : depth.shape[1] : stride]
    z = depth[v, u]
    ok = (z > 0.1) & (z < 8.0) & np.isfinite(z)
    u, v, z = u[ok], v[ok], z[ok]
    x = (u - K[0, 2]) * z / K[0, 0]
    y = (v - K[1, 2]) * z / K[1, 1]
    return np.stack([x, y, z], axis=1)


def seen_fraction(points_a, T_b_a, view_b, tolerance_m=0.10):
    """Fraction of a's points that land on b's measured surface within tolerance_m."""
    if len(points_a) == 0:
        return 0.0
    depth = np.asarray(view_b.depth, dtype=np.float64)
    if view_b.depth_scale:
        depth = depth / view_b.depth_scale
    K = np.asarray(view_b.intrinsics)
    p = points_a @ T_b_a[:3, :3].T + T_b_a[:3, 3]
    front = p[:, 2] > 0.1
    p = p[front]
    u = np.round(K[0, 0] * p[:, 0] / p[:, 2] + K[0, 2]).astype(int)
    v = np.round(K[1, 1] * p[:, 1] / p[:, 2] + K[1, 2]).astype(int)
    inside = (u >= 0) & (u < depth.shape[1]) & (v >= 0) & (v < depth.shape[0])
    d = depth[v[inside], u[inside]]
    agree = (d > 0) & (np.abs(d - p[inside, 2]) < tolerance_m)
    return float(agree.sum()) / len(points_a)


def covisibility(scan_a, scan_b):
    """(smaller, larger) of the two directions' fractions of one frame's depth seen by the other."""
    T_b_a = np.linalg.inv(scan_b.T_world_scan_gt) @ scan_a.T_world_scan_gt
    pa, pb = camera_points(scan_a.views[0]), camera_points(scan_b.views[0])
    both = (seen_fraction(pa, T_b_a, scan_b.views[0]),
            seen_fraction(pb, np.linalg.inv(T_b_a), scan_a.views[0]))
    return min(both), max(both)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", default="../shared/data")
    ap.add_argument("--per-scene", type=int, default=30, help="non-overlapping pairs per scene")
    ap.add_argument("--cross", type=int, default=30, help="cross-scene pairs")
    ap.add_argument("--max-covisibility", type=float, default=0.01,
                    help="same scene: both directions below this")
    ap.add_argument("--low-overlap", type=int, default=30, help="low-overlap pairs per scene")
    ap.add_argument("--low-band", type=float, nargs=2, default=[0.02, 0.15], metavar=("LO", "HI"),
                    help="low overlap: the smaller direction's co-visibility in [LO, HI)")
    ap.add_argument("--seed", type=int, default=0, help="seed of the pair sampling")
    ap.add_argument("--out", default="results/negatives")
    ap.add_argument("--only-scene", action="append", default=[],
                    help="register only the sampled pairs of this scene (sampling unchanged)")
    ap.add_argument("--set", action="append", default=[], help="config override section.key=value")
    ap.add_argument("--prior-error", type=float, nargs=2, metavar=("DEG", "M"),
                    help="register every pair with a motion prior this far from the truth "
                    "(cross-scene pairs: from the identity)")
    ap.add_argument("--prior-tolerance", type=float, nargs=2, metavar=("DEG", "M"),
                    help="the prior's tolerance (default 15 deg, 0.3 m)")
    args = ap.parse_args()
    if args.prior_tolerance and not args.prior_error:
        sys.exit("--prior-tolerance: needs --prior-error (without a prior there is no tolerance)")
    args.prior_tolerance = args.prior_tolerance or [15.0, 0.30]
    if args.prior_error and (min(args.prior_error) < 0 or min(args.prior_tolerance) <= 0):
        sys.exit(f"--prior-error {args.prior_error} / --prior-tolerance {args.prior_tolerance}: "
                 "expected errors >= 0 and tolerances > 0 (degrees, metres)")

    for scene in SCENES:
        if not os.path.isdir(os.path.join(args.data, scene, "frames")):
            sys.exit(f"{os.path.join(args.data, scene)}: scene not found (--data holds {SCENES})")
    if not args.max_covisibility <= args.low_band[0] < args.low_band[1]:
        sys.exit(f"--max-covisibility {args.max_covisibility} and --low-band {args.low_band}: "
                 "expected max-covisibility <= LO < HI (a pair must be one kind or the other)")
    os.makedirs(args.out, exist_ok=True)
    # One generator per kind, so that asking for more of one kind leaves the others' pairs alone.
    rng_same = np.random.default_rng([args.seed, 0])
    rng_cross = np.random.default_rng([args.seed, 1])
    rng_prior = np.random.default_rng([args.seed, 2])
    pipeline = zeroreg.Pipeline(parse_sets(args.set), seed=0)
    chosen = {}  # the scans of the chosen pairs only (sampling reads thousands of frames)

    def load(scene, frame):
        return zeroreg.load_scan(f"{os.path.join(args.data, scene)}@{frame}")

    def scan(scene, frame):
        key = (scene, frame)
        if key not in chosen:
            chosen[key] = load(scene, frame)
        return chosen[key]

    pairs = []  # (kind, target scene, target frame, source scene, source frame, covisibility)
    for scene in SCENES:
        ids = frame_ids(os.path.join(args.data, scene))
        wanted = {"same scene": args.per_scene, "low overlap": args.low_overlap}
        found = {kind: 0 for kind in wanted}
        tries = 0
        seen = set()  # each unordered pair once
        while any(found[k] < wanted[k] for k in wanted) and tries < 50 * sum(wanted.values()):
            tries += 1
            i, j = (int(x) for x in rng_same.choice(ids, size=2, replace=False))
            if (i, j) in seen or (j, i) in seen:
                continue
            seen.add((i, j))
            low, high = covisibility(load(scene, j), load(scene, i))
            if high < args.max_covisibility:
                kind = "same scene"
            elif args.low_band[0] <= low < args.low_band[1]:
                kind = "low overlap"
            else:
                continue
            if found[kind] < wanted[kind]:
                pairs.append((kind, scene, i, scene, j, low))
                found[kind] += 1
        for kind in wanted:
            if found[kind] < wanted[kind]:
                print(f"{scene}: only {found[kind]} {kind} pairs in {tries} tries", file=sys.stderr)
    ids = {scene: frame_ids(os.path.join(args.data, scene)) for scene in SCENES}
    for k in range(args.cross):
        a, b = (SCENES[x] for x in rng_cross.choice(len(SCENES), size=2, replace=False))
        pairs.append(("cross scene", a, int(rng_cross.choice(ids[a])), b,
                      int(rng_cross.choice(ids[b])), 0.0))
    if args.only_scene:
        pairs = [p for p in pairs if p[1] in args.only_scene]
    if not pairs:
        sys.exit("no pairs to register (all counts 0, or none found)")

    records = []
    with open(os.path.join(args.out, "pairs.jsonl"), "w") as out:
        for n, (kind, ts, tf, ss, sf, c) in enumerate(pairs):
            gt = None
            if ss == ts:
                gt = np.linalg.inv(scan(ts, tf).T_world_scan_gt) @ scan(ss, sf).T_world_scan_gt
            prior = {}
            if args.prior_error:
                guess = gt if gt is not None else np.eye(4)
                prior = {"prior": pose_off_by(guess, *args.prior_error, rng_prior),
                         "prior_max_rotation_deg": args.prior_tolerance[0],
                         "prior_max_translation_m": args.prior_tolerance[1]}
            start = time.perf_counter()
            try:
                r = pipeline.register(scan(ss, sf), scan(ts, tf), **prior)
            except (RuntimeError, ValueError) as e:  # a bad frame stops one pair, not the run
                print(f"{ss}@{sf} -> {ts}@{tf}: {e}", file=sys.stderr)
                continue
            seconds = time.perf_counter() - start
            full = r.to_dict()
            verification = full.get("verification", {})
            rec = {"kind": kind, "target": f"{ts}@{tf}", "source": f"{ss}@{sf}",
                   "covisibility": round(c, 4), "valid": bool(r.valid), "path": r.path,
                   "overlap": verification.get("overlap"),
                   "brightness_rank_correlation": verification.get("brightness_rank_correlation"),
                   "reason": r.reason, "time_ms": round(1000 * seconds, 1),
                   "ambiguous": bool(full.get("ambiguous", False)),
                   "candidates": full.get("candidates", []),
                   "alternatives": full.get("alternatives", []),
                   "timings_ms": full.get("timings_ms", {})}
            if prior:
                rec["prior_error"] = args.prior_error
            if gt is not None:
                rec["rotation_error_deg"] = zeroreg.rotation_error_deg(r.T_target_source, gt)
                rec["translation_error_m"] = zeroreg.translation_error_m(r.T_target_source, gt)
            # Without a common surface no transform is right; with one, the suite's criterion.
            rec["right"] = (kind == "low overlap" and rec["rotation_error_deg"] < 15
                            and rec["translation_error_m"] < 0.3)
            records.append(rec)
            out.write(json.dumps(rec) + "\n")
            print(f"[{n + 1}/{len(pairs)}] {kind}: {rec['source']} -> {rec['target']}: "
                  f"{'valid' if r.valid else 'invalid'}, {'right' if rec['right'] else 'wrong'}",
                  file=sys.stderr, flush=True)

    lines = []
    if args.prior_error:
        lines += [f"With a motion prior {args.prior_error[0]:g} deg and {args.prior_error[1]:g} m "
                  f"from the truth (tolerance {args.prior_tolerance[0]:g} deg, "
                  f"{args.prior_tolerance[1]:g} m) on every same-scene pair; cross-scene pairs "
                  f"get the identity moved as far.\n"]
    lines += ["| pairs | scenes | count | valid-right / valid-WRONG / invalid-right / invalid-wrong "
             "| median ms / pair |", "|---|---|---|---|---|"]
    groups = {}
    for rec in records:
        scene = rec["target"].split("@")[0]
        group = (rec["kind"], "any two" if rec["kind"] == "cross scene" else scene)
        groups.setdefault(group, []).append(rec)
    def verdicts(recs):
        count = {(v, ri): 0 for v in (True, False) for ri in (True, False)}
        for r in recs:
            count[(r["valid"], r["right"])] += 1
        return (f"{count[(True, True)]} / {count[(True, False)]} / {count[(False, True)]} / "
                f"{count[(False, False)]}")

    for (kind, scene), recs in groups.items():
        lines.append(f"| {kind} | {scene} | {len(recs)} | {verdicts(recs)} | "
                     f"{statistics.median(r['time_ms'] for r in recs):.0f} |")
    valid_wrong = sum(r["valid"] and not r["right"] for r in records)
    lines.append(f"| all | | {len(records)} | {verdicts(records)} | "
                 f"{statistics.median(r['time_ms'] for r in records):.0f} |")
    for rec in records:
        if rec["valid"] and not rec["right"]:
            lines.append(f"\nVALID-WRONG: {rec['source']} -> {rec['target']} ({rec['kind']}, "
                         f"co-visibility {rec['covisibility']}): {rec['reason']}")
    summary = "\n".join(lines) + "\n"
    with open(os.path.join(args.out, "summary.md"), "w") as f:
        f.write(summary)
    print(summary)
    return 1 if valid_wrong else 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""Compares two suite runs pair by pair: which pairs changed their estimate, verdict or path.

    python3 scripts/compare-runs.py RESULTS_A/NAME RESULTS_B/NAME [LIST ...]

Each argument is a method folder of scripts/bench-suite.sh (RESULTS/<NAME>), holding one folder
per list with a pairs.jsonl. Without LISTs every list present in both is compared. Per list it
prints how many pairs are bit-identical in T_est, valid and path, and for each pair that is not,
the rotation / translation change between the two estimates and both verdicts. A speed change that
should not change results is checked with this: every list must say "identical".
"""
import json
import math
import os
import sys


def load(path):
    records = {}
    with open(path) as f:
        for number, line in enumerate(f, 1):
            line = line.strip()
            if not line:
                continue
            try:
                r = json.loads(line)
            except json.JSONDecodeError as e:
                sys.exit(f"{path}:{number}: not JSON ({e})")
            records[r["key"]] = r
    return records


def rotation_translation_change(a, b):
    """Angle (deg) of R_a^T R_b and |t_a - t_b| (m) of two 4x4 row-major transforms."""
    ra = [[a[i][j] for j in range(3)] for i in range(3)]
    rb = [[b[i][j] for j in range(3)] for i in range(3)]
    trace = sum(ra[k][i] * rb[k][i] for i in range(3) for k in range(3))
    angle = math.degrees(math.acos(max(-1.0, min(1.0, (trace - 1.0) / 2.0))))
    dt = math.sqrt(sum((a[i][3] - b[i][3]) ** 2 for i in range(3)))
    return angle, dt


def verdict(r):
    # 3DMatch / 3DLoMatch records carry the recall error (gt.info) and "registered" follows it;
    # frame-list records have no gt.info, so "right" is the suite's success (RE < 15 deg, TE < 30 cm).
    if r.get("recall_error") is not None:
        right = r.get("registered", False)
    else:
        right = r["rotation_error_deg"] < 15 and r["translation_error_m"] < 0.30
    return ("valid" if r["valid"] else "invalid") + ("/right" if right else "/wrong")


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    a_root, b_root = sys.argv[1], sys.argv[2]
    for root in (a_root, b_root):
        if not os.path.isdir(root):
            sys.exit(f"compare-runs: {root} is not a folder (expected RESULTS/<NAME> of bench-suite)")
    lists = sys.argv[3:] or sorted(
        set(os.listdir(a_root)) & set(os.listdir(b_root)),
    )
    differing = 0
    for name in lists:
        pa, pb = (os.path.join(root, name, "pairs.jsonl") for root in (a_root, b_root))
        if not (os.path.isfile(pa) and os.path.isfile(pb)):
            continue
        a, b = load(pa), load(pb)
        keys = sorted(set(a) & set(b))
        changed = [
            k for k in keys
            if (a[k]["T_est"], a[k]["valid"], a[k].get("path")) !=
            (b[k]["T_est"], b[k]["valid"], b[k].get("path"))
        ]
        only = len(set(a) ^ set(b))
        extra = f", {only} pairs in only one run" if only else ""
        if not changed:
            print(f"{name}: identical ({len(keys)} pairs{extra})")
            continue
        differing += len(changed)
        print(f"{name}: {len(changed)} of {len(keys)} pairs differ{extra}")
        for k in changed:
            angle, dt = rotation_translation_change(a[k]["T_est"], b[k]["T_est"])
            print(f"  {k}: {angle:7.3f} deg {dt:7.4f} m  {verdict(a[k])} [{a[k].get('path')}]"
                  f" -> {verdict(b[k])} [{b[k].get('path')}]")
    sys.exit(1 if differing else 0)


if __name__ == "__main__":
    main()

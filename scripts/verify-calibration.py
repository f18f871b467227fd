#!/usr/bin/env python3
"""How well does the geometric check (verify) separate right from wrong transforms, per list?

For every pair of every list in LISTS (pairs.txt + gt.log), the check is run on the ground-truth
transform (must pass), on slightly perturbed ones (still "right": must mostly pass) and on
transforms perturbed to the edge of "wrong" (RE = 15 deg or TE = 30 cm: must fail), and the
measured evidence (overlap, violation, probe agreement) is written to a JSONL file and summarised.
This is the table docs/CONFIG.md quotes for the verify thresholds.

    ZEROREG_PYTHONPATH=build/python /usr/bin/python3 scripts/verify-calibration.py \
        [--lists ../shared/lists] [--data ../shared/data] [--out results/verify-calibration.jsonl] \
        [--every 1] [--set verify.key=value ...]
"""
import argparse
import json
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.environ.get("ZEROREG_PYTHONPATH", "build/python"))
import zeroreg  # noqa: E402

SCENES = {"redkitchen": "7scenes-redkitchen", "hololens": "hololens-office", "cabinet": "tum-fr3-cabinet"}

# name -> (rotation deg, translation m): about a random axis through a point 2 m in front of the
# target camera, and along a random direction.
PERTURBATIONS = {
    "gt": (0.0, 0.0),
    "right-2deg-3cm": (2.0, 0.03),
    "right-5deg-10cm": (5.0, 0.10),
    "wrong-15deg": (15.0, 0.0),
    "wrong-30cm": (0.0, 0.30),
    "wrong-10deg-20cm": (10.0, 0.20),
}


def read_log(path):
    with open(path) as f:
        lines = [l.split() for l in f if l.strip()]
    out = {}
    for k in range(0, len(lines), 5):
        i, j = int(lines[k][0]), int(lines[k][1])
        out[(i, j)] = np.array([[float(x) for x in lines[k + r]] for r in range(1, 5)])
    return out


def rotation(axis, deg):
    axis = axis / np.linalg.norm(axis)
    a = math.radians(deg)
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + math.sin(a) * K + (1 - math.cos(a)) * K @ K


def perturb(T, deg, metres, rng):
    c = np.array([0.0, 0.0, 2.0])
    D = np.eye(4)
    R = rotation(rng.normal(size=3), deg)
    d = rng.normal(size=3)
    D[:3, :3] = R
    D[:3, 3] = c - R @ c + metres * d / np.linalg.norm(d)
    return D @ T


def config_from_sets(sets):
    config = {}
    for s in sets:
        key, value = s.split("=", 1)
        section, name = key.split(".", 1)
        try:
            value = json.loads(value)
        except json.JSONDecodeError:
            pass
        config.setdefault(section, {})[name] = value
    return config


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--lists", default="../shared/lists")
    ap.add_argument("--data", default="../shared/data")
    ap.add_argument("--out", default="results/verify-calibration.jsonl")
    ap.add_argument("--every", type=int, default=1, help="every k-th pair of each list")
    ap.add_argument("--set", action="append", default=[], help="verify.key=value override")
    args = ap.parse_args()
    config = config_from_sets(args.set)
    os.makedirs(os.path.dirname(args.out) or ".", exist_ok=True)
    summary = {}
    with open(args.out, "w") as out:
        for name in sorted(os.listdir(args.lists)):
            folder = os.path.join(args.lists, name)
            if not os.path.isfile(os.path.join(folder, "gt.log")):
                continue
            data = os.path.join(args.data, SCENES[name.split("-")[0]])
            gt = read_log(os.path.join(folder, "gt.log"))
            rng = np.random.default_rng(0)
            for n, ((i, j), T) in enumerate(sorted(gt.items())):
                if n % args.every:
                    continue
                target = zeroreg.load_scan(f"{data}@{i}")
                source = zeroreg.load_scan(f"{data}@{j}")
                for kind, (deg, metres) in PERTURBATIONS.items():
                    v = zeroreg.verify(source, target, perturb(T, deg, metres, rng), config or None)
                    row = {"list": name, "i": i, "j": j, "kind": kind, **{k: v[k] for k in (
                        "passed", "overlap", "overlap_max", "violation", "probe_contradicted", "score",
                        "residual_rms_m")}}
                    out.write(json.dumps(row) + "\n")
                    s = summary.setdefault((name, kind), [0, 0])
                    s[0] += 1
                    s[1] += bool(v["passed"])
            print(name, "done", file=sys.stderr)
    kinds = list(PERTURBATIONS)
    print("| list | " + " | ".join(kinds) + " |")
    print("|---|" + "---|" * len(kinds))
    for name in sorted({k[0] for k in summary}):
        cells = []
        for kind in kinds:
            n, p = summary[(name, kind)]
            cells.append(f"{p}/{n}")
        print(f"| {name} | " + " | ".join(cells) + " |")
    print("(cells: passed / checked)")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Is the ground truth where the depth says it is? ICP started from the ground truth, per list.

For every pair of every list in LISTS, the pipeline's ICP refinement (zeroreg.refine, config
"refine", no anchors) is started from the ground-truth transform. Where the scans' own depth
agrees with the ground truth, ICP stays put; where it moves the estimate more than 5 cm, any method
that fits the depth (ICP, and every estimate refined by it) lands that far from the ground truth
too, however right it is about the scans. The geometric check's score (zeroreg.verify) at the
ground truth and at the refined transform says which of the two the scans agree with better.
Prints per list: pairs ICP keeps within 5 deg / 5 cm of the ground truth, and of the pairs it moves
farther than 5 cm, those where the check prefers the refined transform. docs/CONFIG.md quotes it.

    ZEROREG_PYTHONPATH=build/python /usr/bin/python3 scripts/gt-consistency.py \
        [--lists ../shared/lists] [--data ../shared/data] [--only REGEX] \
        [--out results/gt-consistency.jsonl] [--set section.key=value ...]
"""
import argparse
import json
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.environ.get("ZEROREG_PYTHONPATH", "build/python"))
import zeroreg  # noqa: E402

SCENES = {"redkitchen": "7scenes-redkitchen", "hololens": "hololens-office", "cabinet": "tum-fr3-cabinet"}


def read_log(path):
    with open(path) as f:
        lines = [line.split() for line in f if line.strip()]
    out = []
    for k in range(0, len(lines), 5):
        i, j = int(lines[k][0]), int(lines[k][1])
        out.append((i, j, np.array([[float(x) for x in lines[k + r]] for r in range(1, 5)])))
    return out


def config_from_sets(sets):
    config = {}
    for item in sets:
        key, value = item.split("=", 1)
        *sections, leaf = key.split(".")
        node = config
        for s in sections:
            node = node.setdefault(s, {})
        node[leaf] = json.loads(value) if value not in ("", None) else value
    return config or None


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--lists", default="../shared/lists")
    ap.add_argument("--data", default="../shared/data")
    ap.add_argument("--only", default=".", help="regex on the list name (default: every list)")
    ap.add_argument("--out", default="results/gt-consistency.jsonl")
    ap.add_argument("--set", action="append", default=[], help="config override section.key=value (JSON value)")
    args = ap.parse_args()
    config = config_from_sets(args.set)
    os.makedirs(os.path.dirname(args.out) or ".", exist_ok=True)
    print("| list | pairs | ICP from GT within 5 deg / 5 cm | moved > 5 cm | of those, check prefers ICP |")
    print("|---|---|---|---|---|")
    with open(args.out, "w") as out:
        for name in sorted(os.listdir(args.lists)):
            folder = os.path.join(args.lists, name)
            if not os.path.isfile(os.path.join(folder, "gt.log")) or not re.search(args.only, name):
                continue
            data = os.path.join(args.data, SCENES[name.split("-")[0]])
            stay = moved = preferred = 0
            entries = read_log(os.path.join(folder, "gt.log"))
            for i, j, T_gt in entries:
                target = zeroreg.load_scan(f"{data}@{i}")
                source = zeroreg.load_scan(f"{data}@{j}")
                refined = zeroreg.refine(source, target, T_gt, config)
                T = refined["T_target_source"]
                te = zeroreg.translation_error_m(T, T_gt)
                re_deg = zeroreg.rotation_error_deg(T, T_gt)
                score_gt = zeroreg.verify(source, target, T_gt, config)["score"]
                score_icp = zeroreg.verify(source, target, T, config)["score"]
                if te < 0.05 and re_deg < 5:
                    stay += 1
                if te >= 0.05:
                    moved += 1
                    preferred += score_icp > score_gt
                out.write(json.dumps({"list": name, "source": j, "target": i, "te_m": te, "re_deg": re_deg,
                                      "fitness": refined["fitness"], "score_gt": score_gt,
                                      "score_icp": score_icp}) + "\n")
            n = len(entries)
            print(f"| {name} | {n} | {stay} ({100.0 * stay / n:.1f} %) | {moved} | {preferred} |", flush=True)


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Object-level table from `zeroreg eval pairs` runs.

    /usr/bin/python3 scripts/object-table.py RESULTS [RESULTS ...] [--common] [--markdown OUT.md]

Reads RESULTS/<setup>/<list>/pairs.jsonl (one `zeroreg eval pairs --list ../shared/lists/<list>
--out RESULTS/<setup>/<list>` run each; scripts/bench-objects.sh makes them) and prints one row per
(list, setup), over the finished pairs (records without "error"):

- objects / view: objects of both scans over their views (frame pairs: one view per scan);
- matches / pair: matched object pairs (after the label filter) per pair;
- precision: matched pairs whose centroids agree within 0.3 m under the ground truth;
- same surface: matched pairs whose visible surfaces coincide under the ground truth (at least a
  fifth of either object's 3D points within 5 cm of the other's; src/eval/object_match_metrics.hpp),
  over the records that carry it ("-" for runs made before it was recorded): a partly seen object
  shifts its centroid, not its surface;
- matchable / pair: the most right matches these objects allow (`objects.matchable`, the
  ceiling): the largest one-to-one set of source/target object pairs with equal labels whose
  centroids agree within 0.3 m under the ground truth; no matcher can get more right from what
  the detectors found ("-" for runs made before it was recorded);
- recall: correct matches over matchable pairs (what the matching makes of what perception gave);
- matchable by surface / pair: the same with the surface test instead of the centroids;
- object path: share of pairs whose returned transform came from the object path;
- rot@5 / trans@5 / success: RE < 5 deg, TE < 5 cm, and RE < 15 deg with TE < 30 cm;
- valid-wrong: pairs the method called valid that are not a success;
- median time per pair (registration only, ms).

Several RESULTS folders are read together (a setup name must appear in one only). --common keeps,
per list, only the pairs every setup of that list has finished (by the records' "key"), so setups
run on different subsets or stopped part way are compared on the same pairs.

Standard library only.
"""
import argparse
import json
import os
import statistics
import sys


def rows_of(path):
    with open(path) as f:
        return [json.loads(line) for line in f if line.strip()]


def summarise(records):
    done = [r for r in records if "error" not in r]
    n = len(done)
    if n == 0:
        return None
    objects = views = matches = correct = 0
    surface_matches = same_surface = 0
    matchable_pairs = matchable = matchable_correct = 0
    surface_pairs = matchable_surface = 0
    for r in done:
        o = r.get("objects", {})
        objects += o.get("source", 0) + o.get("target", 0)
        views += o.get("views_source", 1) + o.get("views_target", 1)
        matches += o.get("matches", 0)
        correct += o.get("correct", 0)
        if "same_surface" in o:
            surface_matches += o.get("matches", 0)
            same_surface += o["same_surface"]
        if "matchable" in o:
            matchable_pairs += 1
            matchable += o["matchable"]
            matchable_correct += o.get("correct", 0)
        if "matchable_same_surface" in o:
            surface_pairs += 1
            matchable_surface += o["matchable_same_surface"]
    success = [r["rotation_error_deg"] < 15 and r["translation_error_m"] < 0.30 for r in done]
    return {
        "pairs": n,
        "objects_per_view": objects / views if views else 0.0,
        "matches_per_pair": matches / n,
        "precision": correct / matches if matches else None,
        "same_surface": same_surface / surface_matches if surface_matches else None,
        "correct_per_pair": correct / n,
        # Records without objects carry no "matchable": none can be matched there.
        "matchable_per_pair": matchable / n if matchable_pairs else None,
        "recall": matchable_correct / matchable if matchable else None,
        "matchable_surface_per_pair": matchable_surface / n if surface_pairs else None,
        "object_path": sum(r.get("path") == "object" for r in done) / n,
        "rot5": sum(r["rotation_error_deg"] < 5 for r in done) / n,
        "trans5": sum(r["translation_error_m"] < 0.05 for r in done) / n,
        "success": sum(success) / n,
        "valid_wrong": sum(r["valid"] and not s for r, s in zip(done, success)),
        "median_ms": statistics.median(r["time_ms"] for r in done),
    }


def pct(x):
    return "-" if x is None else f"{100.0 * x:.1f}"


def per_pair(x):
    return "-" if x is None else f"{x:.2f}"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("results", nargs="+")
    ap.add_argument("--common", action="store_true",
                    help="per list, only the pairs finished in every setup")
    ap.add_argument("--markdown", help="also write the table to this file")
    args = ap.parse_args()
    runs = {}  # (list, setup) -> records
    for results in args.results:
        for setup in sorted(os.listdir(results)):
            setup_dir = os.path.join(results, setup)
            if not os.path.isdir(setup_dir):
                continue
            for lst in sorted(os.listdir(setup_dir)):
                path = os.path.join(setup_dir, lst, "pairs.jsonl")
                if os.path.isfile(path):
                    runs[(lst, setup)] = [r for r in rows_of(path) if "error" not in r]
    if args.common:
        for lst in {k[0] for k in runs}:
            keys = [{r["key"] for r in recs} for (l, _), recs in runs.items() if l == lst]
            shared = set.intersection(*keys)
            for k in [k for k in runs if k[0] == lst]:
                runs[k] = [r for r in runs[k] if r["key"] in shared]
    table = []
    for (lst, setup), records in runs.items():
        s = summarise(records)
        if s is not None:
            table.append((lst, setup, s))
    if not table:
        sys.exit(f"object-table: no RESULTS/<setup>/<list>/pairs.jsonl under {args.results}")
    table.sort(key=lambda t: (t[0], t[1]))
    lines = ["| list | setup | pairs | objects / view | matches / pair | precision (%) | "
             "same surface (%) | correct / pair | matchable / pair | recall (%) | "
             "matchable by surface / pair | object path (%) | rot@5 (%) | trans@5cm (%) | success (%) | "
             "valid-wrong | median (ms) |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for lst, setup, s in table:
        lines.append(f"| {lst} | {setup} | {s['pairs']} | {s['objects_per_view']:.2f} | "
                     f"{s['matches_per_pair']:.2f} | {pct(s['precision'])} | "
                     f"{pct(s['same_surface'])} | {s['correct_per_pair']:.2f} | "
                     f"{per_pair(s['matchable_per_pair'])} | {pct(s['recall'])} | "
                     f"{per_pair(s['matchable_surface_per_pair'])} | {pct(s['object_path'])} | {pct(s['rot5'])} | "
                     f"{pct(s['trans5'])} | {pct(s['success'])} | {s['valid_wrong']} | "
                     f"{s['median_ms']:.0f} |")
    text = "\n".join(lines) + "\n"
    sys.stdout.write(text)
    if args.markdown:
        with open(args.markdown, "w") as f:
            f.write(text)


if __name__ == "__main__":
    main()

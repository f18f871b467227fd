#!/usr/bin/env python3
"""The table of the multi-scene benchmark (scripts/bench-suite.sh), from every summary.json.

    /usr/bin/python3 scripts/suite-table.py RESULTS [--benchmarks-md BENCHMARKS.md]

Reads RESULTS/<name>/<list>/summary.json (one `zeroreg eval` run each; shard folders
"<list>.shard-i-of-N" are skipped, merge them first) and writes RESULTS/suite.md and
RESULTS/suite.json: one row per (list, method).

- Frame-pair lists (`eval pairs --list`): pairs done / selected, rot@5deg and trans@5cm (fraction
  of finished pairs with RE < 5 deg / TE < 5 cm), success (RE < 15 deg and TE < 30 cm), the
  verdict confusion valid-right / valid-WRONG / invalid-right / invalid-wrong (right = success),
  the share of pairs whose path is "object", the median time per pair.
- 3DMatch / 3DLoMatch (`eval 3dmatch`): RR and the same confusion with right = registered
  (over the finished pairs with j > i + 1).

A valid-WRONG count above 0 is bold. With --benchmarks-md FILE the tables also replace the text
between the markers <!-- suite:begin --> and <!-- suite:end --> of FILE. Standard library only.
"""
import argparse
import json
import os
import sys

BEGIN, END = "<!-- suite:begin -->", "<!-- suite:end -->"


def pct(x):
    return "" if x is None else f"{100.0 * x:.1f}"


def verdicts(b):
    wrong = b.get("valid_wrong", 0)
    wrong_text = f"**{wrong}**" if wrong > 0 else str(wrong)
    return f"{b.get('valid_right', 0)} / {wrong_text} / {b.get('invalid_right', 0)} / " \
           f"{b.get('invalid_wrong', 0)}"


def load_rows(results):
    rows = []
    for name in sorted(os.listdir(results)):
        method_dir = os.path.join(results, name)
        if not os.path.isdir(method_dir):
            continue
        for run in sorted(os.listdir(method_dir)):
            if ".shard-" in run:
                continue
            path = os.path.join(method_dir, run, "summary.json")
            if not os.path.isfile(path):
                continue
            with open(path) as f:
                summary = json.load(f)
            for b in summary.get("benchmarks", []):
                row = {
                    "list": b["benchmark"] if summary["protocol"] == "3dmatch" else run,
                    "method": name,
                    "eval_method": summary.get("method", ""),
                    "protocol": summary["protocol"],
                    "summary": os.path.relpath(path, results),
                    "pairs": b.get("pairs", 0),
                    "done": b.get("done", 0),
                    "valid_right": b.get("valid_right", 0),
                    "valid_wrong": b.get("valid_wrong", 0),
                    "invalid_right": b.get("invalid_right", 0),
                    "invalid_wrong": b.get("invalid_wrong", 0),
                    "object_path_share": b.get("object_path_share", 0.0),
                    "median_time_ms": b.get("median_time_ms", 0.0),
                    "paths": b.get("paths", {}),
                }
                if summary["protocol"] == "3dmatch":
                    row["registration_recall"] = b.get("registration_recall", 0.0)
                    row["evaluated"] = b.get("evaluated", 0)
                    row["registered"] = b.get("registered", 0)
                else:
                    row["rot_5deg"] = b.get("rotation_accuracy_deg", {}).get("5", 0.0)
                    row["trans_5cm"] = b.get("translation_accuracy_cm", {}).get("5", 0.0)
                    row["success"] = b.get("success", 0.0)
                rows.append(row)
    rows.sort(key=lambda r: (r["protocol"] == "3dmatch", r["list"], r["method"]))
    return rows


def done_text(r):
    return str(r["pairs"]) if r["done"] == r["pairs"] else f"{r['done']} of {r['pairs']}"


def markdown(rows):
    frames = [r for r in rows if r["protocol"] != "3dmatch"]
    match = [r for r in rows if r["protocol"] == "3dmatch"]
    out = []
    if frames:
        out.append("Frame-pair lists (right = RE < 15 deg and TE < 30 cm):\n")
        out.append("| list | method | pairs | rot@5° (%) | trans@5cm (%) | success (%) | "
                   "valid-right / valid-WRONG / invalid-right / invalid-wrong | object path (%) "
                   "| median ms / pair |")
        out.append("|---|---|---|---|---|---|---|---|---|")
        for r in frames:
            out.append(f"| {r['list']} | {r['method']} | {done_text(r)} | {pct(r['rot_5deg'])} | "
                       f"{pct(r['trans_5cm'])} | {pct(r['success'])} | {verdicts(r)} | "
                       f"{pct(r['object_path_share'])} | {r['median_time_ms']:.0f} |")
        out.append("")
    if match:
        out.append("3DMatch / 3DLoMatch redkitchen (right = registered; pairs with j > i + 1):\n")
        out.append("| benchmark | method | pairs (evaluated) | RR (%) | "
                   "valid-right / valid-WRONG / invalid-right / invalid-wrong | object path (%) "
                   "| median ms / pair |")
        out.append("|---|---|---|---|---|---|---|")
        for r in match:
            out.append(f"| {r['list']} | {r['method']} | {done_text(r)} ({r['evaluated']}) | "
                       f"{pct(r['registration_recall'])} | {verdicts(r)} | "
                       f"{pct(r['object_path_share'])} | {r['median_time_ms']:.0f} |")
        out.append("")
    if not rows:
        out.append("(no finished run)\n")
    return "\n".join(out)


def replace_between_markers(path, text):
    with open(path) as f:
        content = f.read()
    begin, end = content.find(BEGIN), content.find(END)
    if begin < 0 or end < begin:
        sys.exit(f"{path}: expected the markers {BEGIN} and {END} (in that order)")
    content = content[:begin + len(BEGIN)] + "\n" + text + "\n" + content[end:]
    with open(path, "w") as f:
        f.write(content)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", help="results folder of scripts/bench-suite.sh")
    parser.add_argument("--benchmarks-md", metavar="FILE",
                        help="also write the tables between the suite markers of FILE")
    args = parser.parse_args()
    if not os.path.isdir(args.results):
        sys.exit(f"{args.results}: not a folder; expected the RESULTS of scripts/bench-suite.sh")
    rows = load_rows(args.results)
    md = markdown(rows)
    with open(os.path.join(args.results, "suite.md"), "w") as f:
        f.write("# zeroreg benchmark suite\n\n" + md)
    with open(os.path.join(args.results, "suite.json"), "w") as f:
        json.dump({"rows": rows}, f, indent=2)
        f.write("\n")
    if args.benchmarks_md:
        replace_between_markers(args.benchmarks_md, md)
    print(md)
    print(f"wrote {os.path.join(args.results, 'suite.md')} and suite.json ({len(rows)} rows)",
          file=sys.stderr)


if __name__ == "__main__":
    main()

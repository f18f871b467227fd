#!/usr/bin/env python3
"""Scale equivariance: the shared scenes made s times smaller or larger are the same problem.

    python3 scripts/bench-scale.py [--scales 0.1,0.25,4] [--lists a,b] [--every N] [--jobs J]
    python3 scripts/bench-scale.py --table-only      # only print the table of finished runs

A copy of a scene at scale s is the same place s times smaller (s < 1) or larger: the same colour
images and intrinsics, every depth reading and every pose translation multiplied by s. The depth
PNGs of the copy are the original files (linked), read with a depth scale of 1000 / s raw units per
metre instead of 1000: the copy's depth is the original's multiplied by s exactly, so its noise is
the scaled sensor's too (sigma(d) = (a / s) d^2 at the copy's depth d: s times the original's
noise at the same place) and so is its quantisation. Writing the copy as new millimetre PNGs would
instead round s x depth to whole millimetres, a coarser sensor than the scaled one at s < 1.
The ground truth of each list (gt.log) is scaled the same way. Copies go to --copies (default
results/scaled-scenes, git-ignored); runs to --out/s<s>/<list>.

Each run is `zeroreg eval pairs` on the copied list, then scored with the length unit s: success
= RE < 15 deg and TE < 30 cm x s, trans@5cm = TE < 5 cm x s; the unscaled runs (s = 1) are
the reference, taken from --reference (a bench-suite method folder, e.g. results/suite/zeroreg)
when given, else run here. The table gives per list and scale: success, valid-right,
valid-but-wrong, trans@5cm (x s), rot@5, and the differences to s = 1.
"""
import argparse
import json
import math
import os
import subprocess
import sys

DEFAULT_LISTS = "redkitchen-gap60,hololens-gap5,cabinet-gap3,redkitchen-cross"
SCENES = {"redkitchen": "7scenes-redkitchen", "hololens": "hololens-office",
          "cabinet": "tum-fr3-cabinet"}
DEPTH_UNITS_PER_METRE = 1000.0  # ../shared/data: uint16 millimetres


def scene_of(list_dir):
    with open(os.path.join(list_dir, "pairs.txt")) as f:
        for line in f:
            if line.startswith("#") and line[1:].strip().startswith("scene:"):
                return line.split(":", 1)[1].strip()
    scene = SCENES.get(os.path.basename(list_dir).split("-")[0])
    if scene is None:
        sys.exit(f"{list_dir}: no '# scene:' line and no known prefix ({list(SCENES)})")
    return scene


def scaled_pose_text(text, s, where):
    numbers = [float(x) for x in text.split()]
    if len(numbers) != 16:
        sys.exit(f"{where}: expected a 4x4 matrix (16 numbers), found {len(numbers)}")
    rows = [numbers[4 * r:4 * r + 4] for r in range(4)]
    for r in range(3):
        rows[r][3] *= s
    return "\n".join(" ".join(repr(v) for v in row) for row in rows) + "\n"


def copy_scene(data_root, scene, copies, s):
    """The scene at scale s (see the module doc); an existing complete copy is kept."""
    source = os.path.abspath(os.path.join(data_root, scene))
    out = os.path.join(copies, f"s{s:g}", scene)
    done = os.path.join(out, ".complete")
    if os.path.exists(done):
        return out
    frames_in = os.path.join(source, "frames")
    if not os.path.isdir(frames_in):
        sys.exit(f"{source}: no frames/ folder (expected the 3DMatch layout of ../shared/data)")
    frames_out = os.path.join(out, "frames")
    os.makedirs(frames_out, exist_ok=True)
    for name in os.listdir(source):
        path = os.path.join(source, name)
        if os.path.isfile(path) and name.endswith(".txt"):
            link = os.path.join(out, name)
            if not os.path.lexists(link):
                os.symlink(path, link)
    for name in sorted(os.listdir(frames_in)):
        path = os.path.join(frames_in, name)
        target = os.path.join(frames_out, name)
        if name.endswith(".pose.txt"):
            with open(path) as f:
                text = scaled_pose_text(f.read(), s, path)
            with open(target, "w") as f:
                f.write(text)
        elif not os.path.lexists(target):
            os.symlink(path, target)
    open(done, "w").close()
    return out


def copy_list(list_dir, copies, s):
    name = os.path.basename(list_dir.rstrip("/"))
    out = os.path.join(copies, f"s{s:g}", "lists", name)
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(list_dir, "pairs.txt")) as f:
        pairs = f.read()
    with open(os.path.join(out, "pairs.txt"), "w") as f:
        f.write(pairs)
    lines = open(os.path.join(list_dir, "gt.log")).read().split("\n")
    scaled = []
    i = 0
    while i < len(lines):
        if not lines[i].strip():
            i += 1
            continue
        scaled.append(lines[i])
        block = " ".join(lines[i + 1:i + 5])
        scaled.append(scaled_pose_text(block, s, list_dir + "/gt.log").rstrip("\n"))
        i += 5
    with open(os.path.join(out, "gt.log"), "w") as f:
        f.write("\n".join(scaled) + "\n")
    return out


def run(args, list_dir, data_dir, depth_scale, out):
    command = [args.zeroreg, "eval", "pairs", "--list", list_dir, "--data", data_dir,
               "--jobs", str(args.jobs), "--no-progress", "--out", out]
    if depth_scale is not None:
        command += ["--depth-scale", repr(depth_scale)]
    if args.pairs_file:
        command += ["--pairs", args.pairs_file]
    for item in args.set:
        command += ["--set", item]
    print("==", " ".join(command), file=sys.stderr)
    if subprocess.run(command, stdout=subprocess.DEVNULL).returncode not in (0, 1):
        print(f"!! {out} failed (rerun to resume)", file=sys.stderr)
        return False
    return True


def pairs_subset(list_dir, every, out):
    """Every `every`-th pair of the list (from the first), as a --pairs file."""
    rows = [line.split() for line in open(os.path.join(list_dir, "pairs.txt"))
            if line.strip() and not line.startswith("#")]
    with open(out, "w") as f:
        for row in rows[::every]:
            f.write(f"{row[0]} {row[1]}\n")
    return out


def score(path, s):
    if not os.path.exists(path):
        return None
    records = [json.loads(line) for line in open(path) if line.strip()]
    if not records:
        return None
    n = len(records)
    right = [r["rotation_error_deg"] < 15 and r["translation_error_m"] < 0.30 * s
             for r in records]
    return {
        "n": n,
        "success": sum(right),
        "valid_right": sum(1 for r, ok in zip(records, right) if r["valid"] and ok),
        "valid_wrong": sum(1 for r, ok in zip(records, right) if r["valid"] and not ok),
        "trans5": 100.0 * sum(r["translation_error_m"] < 0.05 * s for r in records) / n,
        "rot5": 100.0 * sum(r["rotation_error_deg"] < 5 for r in records) / n,
        "keys": {r["key"].split("/", 1)[1]: (r["valid"], ok) for r, ok in zip(records, right)},
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", default="../shared/data")
    ap.add_argument("--lists-dir", default="../shared/lists")
    ap.add_argument("--lists", default=DEFAULT_LISTS, help="comma-separated list names")
    ap.add_argument("--scales", default="0.1,0.25,4", help="comma-separated s (besides 1)")
    ap.add_argument("--copies", default="results/scaled-scenes")
    ap.add_argument("--out", default="results/scale")
    ap.add_argument("--reference", default="",
                    help="method folder with the unscaled runs (RESULTS/<NAME> of bench-suite); "
                         "without it s = 1 is run here")
    ap.add_argument("--every", type=int, default=1, help="every N-th pair of each list")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--zeroreg", default="build/zeroreg")
    ap.add_argument("--set", action="append", default=[], help="config override section.key=value")
    ap.add_argument("--table-only", action="store_true")
    args = ap.parse_args()
    scales = [float(x) for x in args.scales.split(",") if x]
    if any(not (s > 0) for s in scales) or args.every < 1:
        sys.exit("--scales: expected positive numbers; --every: at least 1")
    lists = [x for x in args.lists.split(",") if x]
    failed = False
    table = []
    for name in lists:
        list_dir = os.path.join(args.lists_dir, name)
        if not os.path.isfile(os.path.join(list_dir, "pairs.txt")):
            sys.exit(f"{list_dir}: no pairs.txt (expected a list folder of ../shared/lists)")
        scene = scene_of(list_dir)
        args.pairs_file = ""
        if args.every > 1:
            os.makedirs(args.out, exist_ok=True)
            args.pairs_file = pairs_subset(list_dir, args.every,
                                           os.path.join(args.out, f"{name}.every{args.every}.txt"))
        reference = (os.path.join(args.reference, name) if args.reference
                     else os.path.join(args.out, "s1", name))
        if not args.table_only and not args.reference:
            failed |= not run(args, list_dir, os.path.join(args.data, scene), None, reference)
        base = score(os.path.join(reference, "pairs.jsonl"), 1.0)
        if base and args.pairs_file:
            wanted = {" ".join([scene] + line.split()) for line in open(args.pairs_file)}
            records = [json.loads(l) for l in open(os.path.join(reference, "pairs.jsonl"))]
            subset = os.path.join(args.out, f"{name}.reference.jsonl")
            with open(subset, "w") as f:
                for r in records:
                    if r["key"].split("/", 1)[1] in wanted:
                        f.write(json.dumps(r) + "\n")
            base = score(subset, 1.0)
        table.append((name, 1.0, base, None))
        for s in scales:
            out = os.path.join(args.out, f"s{s:g}", name)
            if not args.table_only:
                data_dir = copy_scene(args.data, scene, args.copies, s)
                scaled_list = copy_list(list_dir, args.copies, s)
                failed |= not run(args, scaled_list, data_dir, DEPTH_UNITS_PER_METRE / s, out)
            table.append((name, s, score(os.path.join(out, "pairs.jsonl"), s), base))
    print("| list | s | pairs | success | valid-right | valid-but-wrong | trans@5cm·s | rot@5 | "
          "pairs whose verdict or success differs from s = 1 |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, s, m, base in table:
        if m is None:
            print(f"| {name} | {s:g} | (no run) | | | | | | |")
            continue
        changed = ""
        if base:
            keys = sorted(set(m["keys"]) & set(base["keys"]))
            diff = [k for k in keys if m["keys"][k] != base["keys"][k]]
            changed = f"{len(diff)}" + (f" ({', '.join(diff[:6])}{', ...' if len(diff) > 6 else ''})"
                                        if diff else "")
        print(f"| {name} | {s:g} | {m['n']} | {m['success']} | {m['valid_right']} | "
              f"{m['valid_wrong']} | {m['trans5']:.1f} % | {m['rot5']:.1f} % | {changed} |")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()

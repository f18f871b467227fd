#!/usr/bin/env bash
# Prints paper-shaped tables (Tables 1, 3, 4, 5 of the ZeroReg paper) from the results folders
# of scripts/bench-main.sh and scripts/bench-ablation.sh, with the paper's numbers beside ours.
# Folders that do not exist yet are skipped; unfinished runs show their "done" count.
#
#   bash scripts/bench-tables.sh        # RESULTS (default results) holds the run folders
set -euo pipefail

repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo_root"
RESULTS="${RESULTS:-results}" python3 - <<'PY'
import json, os

results = os.environ["RESULTS"]

def load(name):
    path = os.path.join(results, name, "summary.json")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        return {b["benchmark"]: b for b in json.load(f)["benchmarks"]}

def pct(x):
    return "%.1f" % (100 * x)

def match_cells(s, bench):
    b = (s or {}).get(bench)
    if b is None:
        return ["", ""]
    rr = pct(b["registration_recall"])
    if b["done"] < b["pairs"]:
        rr += " (%d/%d done)" % (b["done"], b["pairs"])
    return [rr + " (%d/%d)" % (b["registered"], b["evaluated"]), pct(b["inlier_ratio"])]

def row(cells):
    print("| " + " | ".join(cells) + " |")

# ---- Table 1 ----------------------------------------------------------------------------------
print("\n### Table 1: registration recall (RR) and inlier ratio (IR), 3DMatch / 3DLoMatch\n")
row(["method", "source", "3DMatch RR (%)", "3DMatch IR (%)", "3DLoMatch RR (%)",
     "3DLoMatch IR (%)"])
row(["---"] * 6)
row(["FPFH", "paper (all 8 scenes, 1279 / 1726 pairs)", "40.3", "34.1", "-", "-"])
row(["ZeroReg", "paper (all 8 scenes)", "87.2", "53.9", "52.1", "26.2"])
for name, label in [("3dmatch-zeroreg", "zeroreg (current default config)"),
                    ("3dmatch-fpfh", "FPFH + RANSAC (Open3D 0.16)")]:
    s = load(name)
    if s is not None:
        row([label, "ours, redkitchen 0-19 (103 / 42 pairs)"] + match_cells(s, "3DMatch") +
            match_cells(s, "3DLoMatch"))

# ---- Table 3 ----------------------------------------------------------------------------------
print("\n### Table 3: frame pairs (rotation / translation accuracy and errors)\n")
row(["method", "source", "RE acc 5 / 10 / 45 deg (%)", "RE mean / med (deg)",
     "TE acc 5 / 10 / 25 cm (%)", "TE mean / med (cm)", "pairs"])
row(["---"] * 7)
row(["ZeroReg", "paper (ScanNet, 26K pairs, gap 20)", "71.2 / 87.3 / 97.7", "8.0 / 3.1",
     "23.5 / 60.2 / 85.3", "15.2 / 8.9", "26K"])
for gap in (20, 60):
    for suffix, label in [("zeroreg", "zeroreg (current default)"),
                          ("zeroreg-sift", "zeroreg, SIFT features"),
                          ("fpfh", "FPFH + RANSAC (Open3D 0.16)")]:
        s = load("pairs-g%d-%s" % (gap, suffix))
        if s is None:
            continue
        b = s["frames-g%d" % gap]
        ra, ta = b["rotation_accuracy_deg"], b["translation_accuracy_cm"]
        row([label, "ours, redkitchen, gap %d" % gap,
             " / ".join(pct(ra[k]) for k in ("5", "10", "45")),
             "%.2f / %.2f" % (b["rotation_error_deg"]["mean"], b["rotation_error_deg"]["median"]),
             " / ".join(pct(ta[k]) for k in ("5", "10", "25")),
             "%.1f / %.1f" % (b["translation_error_cm"]["mean"],
                              b["translation_error_cm"]["median"]),
             "%d / %d" % (b["done"], b["pairs"])])

# ---- Tables 4 and 5 (scripts/bench-ablation.sh writes ablation-<row>) -------------------------
rows = []
listing = os.path.join(results, "ablation-rows.txt")
if os.path.exists(listing):
    with open(listing) as f:
        rows = [line.rstrip("\n").split("|") for line in f if line.strip()]
if rows:
    print("\n### Tables 4 and 5: ablations (3DMatch / 3DLoMatch, ours on redkitchen 0-19)\n")
    row(["row", "configuration", "paper 3DMatch RR / IR (%) (Lo = 3DLoMatch)", "3DMatch RR (%)", "3DMatch IR (%)",
         "3DLoMatch RR (%)", "3DLoMatch IR (%)"])
    row(["---"] * 7)
    for r in rows:
        rid, label, paper = r[0], r[1], r[2]
        s = load("ablation-" + rid)
        cells = match_cells(s, "3DMatch") + match_cells(s, "3DLoMatch") if s else ["not run"] * 4
        row([rid, label, paper] + cells)
PY

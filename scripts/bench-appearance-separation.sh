#!/usr/bin/env bash
# How well the colour appearance descriptor tells right from wrong object matches:
# registers every 12th pair (offset 5) of the redkitchen and hololens lists with the
# ensemble detector and a negligible appearance weight (1e-3, so the matching is the one without
# appearance), then prints, per list, the Bhattacharyya coefficient BC = cos(a_j, a_k) of the
# matched pairs whose centroids agree within 0.3 m under the ground truth (correct) and of the
# others (wrong), and what a BC threshold would keep. For an equal-label pair
# C = 2 - lambda (1 - BC), so BC = 1 - (2 - C) / lambda is read back from the result's C.
#
#   bash scripts/bench-appearance-separation.sh [OUT=results/appearance-separation]
#
# EXTRA: further register options, e.g. EXTRA="--set segmenter.backend=sam" for the SAM embedding
# descriptor (objects.appearance = auto); its cosine is in [-1, 1], so "BC" below reads as that
# cosine. Use a separate OUT per EXTRA (finished pairs are kept).
set -euo pipefail
repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo_root"
out="${1:-results/appearance-separation}"
read -ra extra <<<"${EXTRA:-}"
bin="${ZEROREG_BIN:-build/zeroreg}"
mkdir -p "$out"
for list in redkitchen-gap20 redkitchen-gap60 redkitchen-cross hololens-gap1 hololens-gap5 hololens-cross; do
  case "$list" in redkitchen-*) data=7scenes-redkitchen ;; *) data=hololens-office ;; esac
  grep -v '^#' "../shared/lists/$list/pairs.txt" | awk 'NF == 2 && NR % 12 == 5' |
    while read -r i j; do
      f="$out/$list-$i-$j.json"
      [[ -s "$f" ]] && continue  # resumable
      "$bin" register --source "../shared/data/$data@$j" --target "../shared/data/$data@$i" \
        --set detector.backend=ensemble --set object_match.appearance_weight=0.001 \
        --set method.point_level=false --set refine.enabled=false "${extra[@]}" --out "$f" \
        >/dev/null 2>&1 || {
        # Exit code 1 = registered but not valid (common without the point level): the JSON with
        # the object matches is written all the same. Anything else is a failure.
        rc=$?
        [[ $rc -eq 1 && -s "$f" ]] || echo "bench-appearance-separation: $list $i $j failed ($rc)" >&2
      }
    done
done
/usr/bin/python3 - "$out" <<'PY'
import glob, json, os, statistics, sys
import numpy as np
lam = 0.001
rows = {}
for f in sorted(glob.glob(os.path.join(sys.argv[1], "*.json"))):
    name = os.path.basename(f).rsplit("-", 2)[0]
    j = json.load(open(f))
    T = np.array(j["ground_truth"]["T_target_source"])
    ob = j["result"].get("objects", {})
    for m in ob.get("matches", []):
        cs = np.array(ob["source"][m["source"]]["centroid"] + [1.0])
        ct = np.array(ob["target"][m["target"]]["centroid"])
        ok = np.linalg.norm((T @ cs)[:3] - ct) < 0.3
        rows.setdefault(name, []).append((ok, 1 - (2 - m["node_similarity"]) / lam))
everything = [r for v in rows.values() for r in v]
def q(v):
    return (f"n={len(v)} median {statistics.median(v):.2f} p10 {np.percentile(v, 10):.2f} "
            f"p90 {np.percentile(v, 90):.2f}") if v else "n=0"
for name, rs in sorted(rows.items()) + [("all", everything)]:
    print(f"{name}: correct {q([b for ok, b in rs if ok])} | wrong {q([b for ok, b in rs if not ok])}")
good = sum(ok for ok, _ in everything)
for t in (-0.2, 0.0, 0.2, 0.3, 0.5, 0.6, 0.7, 0.8):
    kg = sum(1 for ok, b in everything if ok and b >= t)
    kw = sum(1 for ok, b in everything if not ok and b >= t)
    print(f"BC >= {t}: keeps {kg}/{good} correct, {kw}/{len(everything) - good} wrong")
PY

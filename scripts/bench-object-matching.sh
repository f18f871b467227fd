#!/usr/bin/env bash
# Object-level matching quality on the redkitchen frame pairs (i, i+20), i = 0..970:
# a matched object pair is correct when the two centroids agree within 0.3 m under the ground
# truth. Prints precision and mean correct matches per pair, with and without the scene graph and
# CLIP, and the median time of detection, segmentation and object matching per pair.
#
#   bash scripts/bench-object-matching.sh [OUT=results/object-matching] [JOBS=2]
set -euo pipefail
repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo_root"
out="${1:-results/object-matching}"
jobs="${2:-2}"
bin="${ZEROREG_BIN:-build/zeroreg}"
data="../shared/data/7scenes-redkitchen"
declare -A variants=(
  [full]=""
  [no-graph]="--set method.scene_graph=false"
  [no-clip]="--set method.clip=false"
  [no-graph-no-clip]="--set method.scene_graph=false --set method.clip=false"
)
for name in full no-graph no-clip no-graph-no-clip; do
  mkdir -p "$out/$name"
  for ((i = 0; i <= 970; i += 10)); do
    [[ -s "$out/$name/$i.json" ]] && continue  # resumable
    echo "$bin register --source $data@$((i + 20)) --target $data@$i --set refine.enabled=false ${variants[$name]} --out $out/$name/$i.json"
  done
done | xargs -P "$jobs" -I{} sh -c '{} > /dev/null 2>&1 || true'
/usr/bin/python3 - "$out" <<'PY'
import json, os, statistics, sys
import numpy as np
out = sys.argv[1]
print("| variant | pairs | matched object pairs | correct | precision (%) | correct / pair |")
print("|---|---|---|---|---|---|")
times = {}
for name in ["full", "no-graph", "no-clip", "no-graph-no-clip"]:
    pairs = matches = correct = 0
    for f in sorted(os.listdir(f"{out}/{name}")):
        j = json.load(open(f"{out}/{name}/{f}"))
        T = np.array(j["ground_truth"]["T_target_source"])
        objects = j["result"].get("objects", {"source": [], "target": [], "matches": []})
        pairs += 1
        for m in objects["matches"]:
            c_s = np.array(objects["source"][m["source"]]["centroid"] + [1.0])
            c_t = np.array(objects["target"][m["target"]]["centroid"])
            matches += 1
            correct += int(np.linalg.norm((T @ c_s)[:3] - c_t) < 0.3)
        if name == "full":
            for stage in ("detect", "segment", "object_match"):
                times.setdefault(stage, []).append(j["result"]["timings_ms"].get(stage, 0.0))
    precision = 100.0 * correct / matches if matches else 0.0
    print(f"| {name} | {pairs} | {matches} | {correct} | {precision:.1f} | {correct / max(pairs, 1):.2f} |")
print()
for stage, values in times.items():
    print(f"median {stage} per pair (both scans): {statistics.median(values):.1f} ms")
PY

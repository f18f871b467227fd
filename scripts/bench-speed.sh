#!/usr/bin/env bash
# Speed and memory of the default pipeline per frame pair (issue 6): runs `zeroreg register` on
# redkitchen pairs (i, i+GAP) for i = 0, STEP, ... (N pairs), and prints the median wall time per
# stage (from each result's timings_ms, models already loaded) and the peak RSS of the process.
#
#   bash scripts/bench-speed.sh [N=15] [GAP=20] [STEP=60] [extra register options...]
set -euo pipefail
repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo_root"
n="${1:-15}"; gap="${2:-20}"; step="${3:-60}"; shift $(( $# < 3 ? $# : 3 ))
bin="${ZEROREG_BIN:-build/zeroreg}"
data="../shared/data/7scenes-redkitchen"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
for ((k = 0; k < n; ++k)); do
  i=$((k * step))
  # GNU time's %M: peak resident set size of the process, KiB.
  /usr/bin/time -f "%M" -o "$out/rss-$k.txt" "$bin" register --source "$data@$((i + gap))" \
    --target "$data@$i" --out "$out/result-$k.json" "$@" > /dev/null 2>&1 || true
done
/usr/bin/python3 - "$out" "$n" <<'PY'
import json, statistics, sys, glob
out, n = sys.argv[1], int(sys.argv[2])
stages, rss = {}, []
for k in range(n):
    result = json.load(open(f"{out}/result-{k}.json"))["result"]
    for stage, ms in result["timings_ms"].items():
        stages.setdefault(stage, []).append(ms)
    rss.append(int(open(f"{out}/rss-{k}.txt").read().split()[-1]) / 1024)
print(f"{n} pairs; median wall time per stage (ms):")
for stage, values in stages.items():
    print(f"  {stage:14s} {statistics.median(values):8.1f}   (min {min(values):.1f}, max {max(values):.1f})")
print(f"peak RSS per process: median {statistics.median(rss):.0f} MiB, max {max(rss):.0f} MiB")
PY

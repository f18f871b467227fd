#!/usr/bin/env bash
# The main benchmarks of BENCHMARKS.md: paper Table 1 (3DMatch / 3DLoMatch registration recall on
# the redkitchen fragments 0-19 rebuilt from RGB-D) and Table 3 (frame pairs, gaps 20 and 60),
# for zeroreg (current default config), zeroreg with SIFT features and Open3D FPFH + RANSAC.
#
#   bash scripts/bench-main.sh                 # everything (hours on 2 cores; resumable)
#   bash scripts/bench-main.sh 3dmatch         # only Table 1
#   bash scripts/bench-main.sh pairs           # only Table 3
#
# Environment: ZEROREG_BIN (default build/zeroreg), JOBS (default 2), RESULTS (default results),
# EXTRA (more options for every run, e.g. "--limit 5" for a quick try). Each run writes
# $RESULTS/<name>/{pairs.jsonl,summary.json,summary.md}; rerunning skips finished pairs. The
# tables are printed at the end (scripts/bench-tables.sh).
set -euo pipefail

repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo_root"
bin="${ZEROREG_BIN:-build/zeroreg}"
jobs="${JOBS:-2}"
results="${RESULTS:-results}"
read -r -a extra <<< "${EXTRA:-}"
data="../shared/data/7scenes-redkitchen"
gt="../shared/data/3dmatch-gt"
what="${1:-all}"

run() {  # name, then zeroreg eval arguments
  local name="$1"
  shift
  echo "== $name: $bin eval $*" >&2
  "$bin" eval "$@" --jobs "$jobs" --out "$results/$name" "${extra[@]}"
}

if [[ "$what" == all || "$what" == 3dmatch ]]; then
  # Fusion of the 20 fragments happens once (cache/fragments), then both methods reuse it.
  run 3dmatch-zeroreg 3dmatch --data "$data" --gt "$gt" --method zeroreg
  run 3dmatch-fpfh 3dmatch --data "$data" --gt "$gt" --method fpfh
fi
if [[ "$what" == all || "$what" == pairs ]]; then
  for gap in 20 60; do
    run "pairs-g$gap-zeroreg" pairs --data "$data" --gap "$gap" --method zeroreg
    run "pairs-g$gap-zeroreg-sift" pairs --data "$data" --gap "$gap" --method zeroreg \
      --features sift
    run "pairs-g$gap-fpfh" pairs --data "$data" --gap "$gap" --method fpfh
  done
fi
RESULTS="$results" bash scripts/bench-tables.sh

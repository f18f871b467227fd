#!/usr/bin/env bash
# How the pipeline behaves on sensors of other resolutions; a benchmark, not a test (BENCHMARKS.md
# "Capture conditions", docs/CONFIG.md "Pixel grids follow the image size").
#
#   bash scripts/bench-resolution.sh [LIST ...]        (default: redkitchen-gap60)
#
# Each scene the lists use is copied at every size of SIZES (default "1280x960 320x240") into
# cache/resized/WxH/<scene> (build/zeroreg-resize-scene: colour resampled, depth nearest, the
# intrinsics scaled; made once, then reused), the lists run on those copies through
# scripts/bench-suite.sh (METHODS=zeroreg, DATA=the copies) into RESULTS/WxH (default
# results/resolution), and the table of each size is printed (scripts/suite-table.py). JOBS and
# EXTRA go to bench-suite.sh as they are (EXTRA="--set verify.pixel_stride=4" compares with a
# fixed grid). DEPTH_NOISE=A (metres at 1 m) also adds sigma(d) = A d^2 Gaussian depth noise to
# the copies (a noisier sensor; folders WxH-noiseA). A rerun resumes finished pairs: delete the
# results folder to measure again.
set -euo pipefail
repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo_root"
resize="${RESIZE_BIN:-build/zeroreg-resize-scene}"
data_root="${DATA:-../shared/data}"
results="${RESULTS:-results/resolution}"
read -r -a sizes <<< "${SIZES:-1280x960 320x240}"
noise="${DEPTH_NOISE:-0}"
suffix=""
[[ "$noise" == 0 ]] || suffix="-noise$noise"
lists=("$@")
[[ ${#lists[@]} -gt 0 ]] || lists=(redkitchen-gap60)
if [[ ! -x "$resize" ]]; then
  echo "bench-resolution: $resize not found; build first (bash scripts/setup.sh)" >&2
  exit 2
fi

filter="^($(IFS='|'; echo "${lists[*]}"))\$"
for size in "${sizes[@]}"; do
  if [[ ! "$size" =~ ^([0-9]+)x([0-9]+)$ ]]; then
    echo "bench-resolution: size '$size' in SIZES is not WIDTHxHEIGHT (e.g. 1280x960)" >&2
    exit 2
  fi
  width="${BASH_REMATCH[1]}" height="${BASH_REMATCH[2]}"
  for list in "${lists[@]}"; do
    case "$list" in  # the scene of each list of ../shared/lists (lists/README.md)
      redkitchen-*) scene=7scenes-redkitchen ;;
      hololens-*) scene=hololens-office ;;
      cabinet-*) scene=tum-fr3-cabinet ;;
      *) echo "bench-resolution: no scene known for list '$list'" >&2; exit 2 ;;
    esac
    "$resize" "$data_root/$scene" "cache/resized/$size$suffix/$scene" "$width" "$height" "$noise"
  done
  # A failed run (reported by bench-suite.sh) must not stop the other sizes.
  METHODS=zeroreg DATA="cache/resized/$size$suffix" RESULTS="$results/$size$suffix" \
    LIST_FILTER="$filter" \
    bash scripts/bench-suite.sh run || status=1
done
for size in "${sizes[@]}"; do
  echo "## $size$suffix"
  if [[ -f "$results/$size$suffix/suite.md" ]]; then
    cat "$results/$size$suffix/suite.md"
  else
    echo "(no table: every run of this size failed)"
  fi
done
exit "${status:-0}"

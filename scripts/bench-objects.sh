#!/usr/bin/env bash
# The object level on every pair list of ../shared/lists for the detector
# setups (YOLOX-Nano alone, the default's PicoDet top-up below 3 YOLOX objects, both detectors on
# every view), then the table of scripts/object-table.py.
#
#   bash scripts/bench-objects.sh [RESULTS=results/objects]
#
# Environment:
#   EVERY    evaluate every EVERY-th pair of each list (default 1 = all; the subset is written to
#            RESULTS/subsets/<list>.txt and passed as --pairs, so it is spread over the list, not
#            its first pairs as --limit would be)
#   JOBS     --jobs of every run (default 2)
#   SETUPS   space-separated NAME:OPTIONS entries, OPTIONS comma-separated --set values (default:
#            the three setups below; appearance: add object_match.appearance_weight=0)
#   LISTS    default ../shared/lists; DATA default ../shared/data; ZEROREG_BIN default build/zeroreg
# Every run resumes (finished pairs are kept).
set -uo pipefail
repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo_root"
results="${1:-results/objects}"
every="${EVERY:-1}"
jobs="${JOBS:-2}"
lists="${LISTS:-../shared/lists}"
data="${DATA:-../shared/data}"
bin="${ZEROREG_BIN:-build/zeroreg}"
setups="${SETUPS:-yolox:detector.backend=yolox ensemble-below3: ensemble:detector.ensemble_below=0}"

scene_of() {  # list name -> data folder
  case "$1" in
    redkitchen-*) echo 7scenes-redkitchen ;;
    hololens-*) echo hololens-office ;;
    cabinet-*) echo tum-fr3-cabinet ;;
    *) echo "bench-objects: no data folder known for list $1" >&2; return 1 ;;
  esac
}

mkdir -p "$results/subsets"
failed=0
for list_dir in "$lists"/*/; do
  list="$(basename "$list_dir")"
  [[ -f "$list_dir/pairs.txt" ]] || continue
  scene="$(scene_of "$list")" || { failed=1; continue; }
  subset="$results/subsets/$list.txt"
  grep -v '^#' "$list_dir/pairs.txt" | awk -v k="$every" 'NF == 2 && (NR - 1) % k == 0' >"$subset"
  for entry in $setups; do
    name="${entry%%:*}"
    opts=()
    IFS=',' read -ra sets <<<"${entry#*:}"
    for s in "${sets[@]}"; do [[ -n "$s" ]] && opts+=(--set "$s"); done
    echo "bench-objects: $list / $name ($(wc -l <"$subset") pairs)"
    "$bin" eval pairs --list "$list_dir" --data "$data/$scene" --pairs "$subset" \
      --out "$results/$name/$list" --jobs "$jobs" --no-progress "${opts[@]}" >/dev/null ||
      { echo "bench-objects: $list / $name failed" >&2; failed=1; }
  done
done
/usr/bin/python3 scripts/object-table.py "$results" --markdown "$results/objects.md"
exit "$failed"

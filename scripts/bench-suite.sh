#!/usr/bin/env bash
# The multi-scene benchmark: every pair list of ../shared/lists plus 3DMatch / 3DLoMatch
# redkitchen, for a set of methods and named configs, then one table (scripts/suite-table.py).
#
#   bash scripts/bench-suite.sh                     # run everything, then write the table
#   bash scripts/bench-suite.sh table               # only (re)write the table
#   bash scripts/bench-suite.sh merge               # merge SHARD=i/N folders, then the table
#
# Environment:
#   METHODS      space-separated entries METHOD[:NAME[:OPTIONS]] (default "zeroreg sift orb fpfh").
#                METHOD is a --method of `zeroreg eval`; NAME names the results folder (default
#                METHOD); OPTIONS are extra options of that entry, comma-separated, each written
#                with '=' (no spaces), e.g. "zeroreg:no-icp:--set=refine.enabled=false" or
#                "zeroreg:sift-feat:--features=sift,--seed=1".
#   LISTS        folder of list folders (default ../shared/lists); a list folder holds pairs.txt
#                and gt.log. Its data folder: "# scene: NAME" in pairs.txt, else the list's row of
#                LISTS/README.md, else by prefix (redkitchen-*, hololens-*, cabinet-*), under DATA.
#   DATA         data folder (default ../shared/data)
#   LIST_FILTER  extended regex on the list name; "3dmatch" is the name of the 3DMatch/3DLoMatch
#                run (default: everything; frame lists only: LIST_FILTER='^(redkitchen|hololens|cabinet)-')
#   RESULTS      results folder (default results/suite): RESULTS/<NAME>/<list>/ per run
#   JOBS         --jobs of every run (default 2)
#   SHARD        i/N: passed as --shard, results in RESULTS/<NAME>/<list>.shard-i-of-N; after all
#                shards ran, `bash scripts/bench-suite.sh merge` merges them into RESULTS/<NAME>/<list>
#   EXTRA        more options for every run, e.g. EXTRA="--limit 5" for a quick try
#   ZEROREG_BIN  default build/zeroreg
# Every run resumes (rerunning skips finished pairs). A run that fails is reported and the
# suite goes on with the next one; the exit code is 1 if any failed.
set -uo pipefail

repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo_root"
bin="${ZEROREG_BIN:-build/zeroreg}"
jobs="${JOBS:-2}"
results="${RESULTS:-results/suite}"
lists="${LISTS:-../shared/lists}"
data_root="${DATA:-../shared/data}"
filter="${LIST_FILTER:-.}"
shard="${SHARD:-}"
read -r -a methods <<< "${METHODS:-zeroreg sift orb fpfh}"
read -r -a extra <<< "${EXTRA:-}"
what="${1:-run}"
python="${PYTHON:-/usr/bin/python3}"
[[ -x "$python" ]] || python=python3

table() {
  "$python" scripts/suite-table.py "$results"
}

# Scene (data folder name) of a list folder.
list_scene() {
  local dir="$1" name
  name="$(basename "$dir")"
  local scene
  scene="$(sed -n 's/^#[[:space:]]*scene:[[:space:]]*\([^[:space:]]*\).*/\1/p' "$dir/pairs.txt" | head -n 1)"
  if [[ -z "$scene" && -f "$lists/README.md" ]]; then
    scene="$(grep -E "^\| *\`$name\` *\|" "$lists/README.md" | head -n 1 |
      sed -n 's/^| *`[^`]*` *| *`\([^`]*\)`.*/\1/p')"
  fi
  if [[ -z "$scene" ]]; then
    case "$name" in
      redkitchen-*) scene=7scenes-redkitchen ;;
      hololens-*) scene=hololens-office ;;
      cabinet-*) scene=tum-fr3-cabinet ;;
    esac
  fi
  echo "$scene"
}

failed=()
run_one() {  # out folder, then zeroreg eval arguments
  local out="$1"
  shift
  local shard_args=()
  if [[ -n "$shard" ]]; then
    shard_args=(--shard "$shard")
    out="$out.shard-${shard%/*}-of-${shard#*/}"
  fi
  echo "== $out: $bin eval $* --jobs $jobs ${shard_args[*]} ${extra[*]}" >&2
  if ! "$bin" eval "$@" --jobs "$jobs" --no-progress "${shard_args[@]}" "${extra[@]}" \
    --out "$out" > /dev/null; then
    echo "!! $out failed (rerun to retry; finished pairs are kept)" >&2
    failed+=("$out")
  fi
}

merge_all() {
  local dir base
  for dir in "$results"/*/*.shard-0-of-*; do
    [[ -d "$dir" ]] || continue
    base="${dir%.shard-0-of-*}"
    echo "== merge $base.shard-*" >&2
    "$bin" eval merge "$base".shard-*-of-* --out "$base" > /dev/null || failed+=("$base")
  done
}

if [[ "$what" == table ]]; then
  table
  exit $?
fi
if [[ "$what" == merge ]]; then
  merge_all
  table
  [[ ${#failed[@]} -eq 0 ]]
  exit $?
fi
if [[ "$what" != run ]]; then
  echo "usage: bash scripts/bench-suite.sh [run|table|merge]" >&2
  exit 2
fi

for entry in "${methods[@]}"; do
  IFS=: read -r method name options <<< "$entry"
  name="${name:-$method}"
  method_args=()
  if [[ -n "${options:-}" ]]; then IFS=, read -r -a method_args <<< "$options"; fi
  for dir in "$lists"/*/; do
    dir="${dir%/}"
    [[ -f "$dir/pairs.txt" ]] || continue
    list="$(basename "$dir")"
    [[ "$list" =~ $filter ]] || continue
    scene="$(list_scene "$dir")"
    if [[ -z "$scene" || ! -d "$data_root/$scene" ]]; then
      echo "!! $list: no data folder for scene '$scene' under $data_root; skipped" >&2
      failed+=("$results/$name/$list")
      continue
    fi
    run_one "$results/$name/$list" pairs --list "$dir" --data "$data_root/$scene" \
      --method "$method" "${method_args[@]}"
  done
  if [[ "3dmatch" =~ $filter ]]; then
    run_one "$results/$name/3dmatch" 3dmatch --data "$data_root/7scenes-redkitchen" \
      --gt "$data_root/3dmatch-gt" --method "$method" "${method_args[@]}"
  fi
done
table
if [[ ${#failed[@]} -gt 0 ]]; then
  echo "failed runs: ${failed[*]}" >&2
  exit 1
fi

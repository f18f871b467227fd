#!/usr/bin/env bash
# Ablations on 3DMatch / 3DLoMatch (redkitchen fragments 0-19 rebuilt from RGB-D): the rows of the
# paper's Table 4 that can run here, and Table 5 (number of views per fragment). Every row is one
# `zeroreg eval 3dmatch` run that differs from the full method only by config overrides.
#
#   bash scripts/bench-ablation.sh             # all rows
#   bash scripts/bench-ablation.sh a sift      # only these rows
#
# Environment: ZEROREG_BIN (default build/zeroreg), JOBS (default 2), RESULTS (default results),
# EXTRA (options for every run, e.g. "--limit 5"). Row r writes $RESULTS/ablation-<r>/; reruns
# resume. The table is printed by scripts/bench-tables.sh at the end.
set -euo pipefail

repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo_root"
bin="${ZEROREG_BIN:-build/zeroreg}"
jobs="${JOBS:-2}"
results="${RESULTS:-results}"
read -r -a extra <<< "${EXTRA:-}"

# ---- The rows: id | label | paper's 3DMatch RR / IR | options of `zeroreg eval 3dmatch` -------
# A row is the full method plus config overrides (MethodConfig in include/zeroreg/config.hpp holds
# the Table 4 switches). To add a row, add one line with its options; nothing else changes.
# The paper's rows we cannot run as the paper did, and why:
#   (g) point level with SuperGlue: no SuperGlue (nor LoFTR) weights here; the "mnn" row swaps the
#       point matcher instead (mutual nearest neighbours for Sinkhorn);
#   Table 4(b) (YOLOv10 / Florence-2 / SAM v1 / SAM2 combinations): none of those weights here;
#       the detector is YOLOX-Nano and the segmenter GrabCut + depth (DESIGN §2).
#   (d) w/o segmentation is approximated by the "box" segmenter (the detection box as the mask).
rows=(
  "full|Full (zeroreg, current default config; = Table 5, 3 views)|87.2 / 53.9 (Lo 52.1 / 26.2)|--method zeroreg"
  "a|(a) w/o object level: whole-image features|73.3 / 50.2|--method image"
  "b|(b) w/o point level: object centroids only|71.3 / -|--method zeroreg --set method.point_level=false"
  "c|(c) w/o detection: depth-region proposals|78.5 / 50.9|--method zeroreg --set method.detection=false"
  "d|(d) w/o segmentation: box masks|85.1 / 52.8|--method zeroreg --set segmenter.backend=box"
  "e|(e) w/o scene graph|83.2 / 51.8|--method zeroreg --set method.scene_graph=false"
  "f|(f) w/o CLIP|84.5 / 52.0|--method zeroreg --set method.clip=false"
  "mnn|point matcher mutual NN instead of Sinkhorn (cf. (g))|81.6 / 51.2 (g)|--method zeroreg --set match.method=mutual_nn"
  "sift|point features SIFT instead of XFeat (paper: LoFTR)|-|--method zeroreg --features sift"
  "views1|Table 5: 1 view per fragment|85.2 / 51.9 (Lo 50.1 / 23.9)|--method zeroreg --views 1"
  "views2|Table 5: 2 views per fragment|87.0 / 53.5 (Lo 51.8 / 25.6)|--method zeroreg --views 2"
)

mkdir -p "$results"
: > "$results/ablation-rows.txt"
for row in "${rows[@]}"; do
  IFS='|' read -r id label paper options <<< "$row"
  echo "$id|$label|$paper" >> "$results/ablation-rows.txt"
  selected=1
  if [[ $# -gt 0 ]]; then
    selected=0
    for wanted in "$@"; do [[ "$wanted" == "$id" ]] && selected=1; done
  fi
  [[ $selected == 1 ]] || continue
  echo "== ablation $id: $bin eval 3dmatch $options" >&2
  # shellcheck disable=SC2086  # options are word lists by design
  "$bin" eval 3dmatch --data ../shared/data/7scenes-redkitchen --gt ../shared/data/3dmatch-gt \
    $options --jobs "$jobs" --out "$results/ablation-$id" "${extra[@]}"
done
RESULTS="$results" bash scripts/bench-tables.sh

#!/usr/bin/env bash
# The README's main command: installs and builds zeroreg (scripts/setup.sh), fetches and verifies
# the models, then registers real frame 20 of 7-Scenes redkitchen onto frame 0, printing the
# transform, the verdict and the error against the dataset's ground truth, and writing the JSON
# result to results/demo/result.json.
#
#   bash scripts/demo.sh [extra zeroreg register options, e.g. --features sift]
set -euo pipefail

repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo_root"
build_dir="${ZEROREG_BUILD_DIR:-build}"
data="../shared/data/7scenes-redkitchen"
if [[ ! -d "$data/frames" ]]; then
  echo "demo: $data not found; the demo needs the shared data folder beside the repo" >&2
  exit 2
fi

bash scripts/setup.sh
bash scripts/fetch-assets.sh
mkdir -p results/demo
"$build_dir/zeroreg" register --source "$data@20" --target "$data@0" \
  --out results/demo/result.json "$@"

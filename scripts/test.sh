#!/usr/bin/env bash
# The project's test command (README): install/build, fetch and verify the models, run the
# C++ tests, then install the library and the Python package the way users do and run the
# Python tests and the bit-for-bit comparison against them (scripts/check-install.sh).
#
#   bash scripts/test.sh
set -euo pipefail

repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo_root"
build_dir="${ZEROREG_BUILD_DIR:-build}"

bash scripts/setup.sh
bash scripts/fetch-assets.sh
# The tests' ONNX Runtime graph cache (inference.graph_cache = auto) lives in the build folder, not
# in the user's ~/.cache: a fresh build tests the cold path, later runs the warm one.
case "$build_dir" in
  /*) default_cache="$build_dir/test-cache" ;;
  *) default_cache="$repo_root/$build_dir/test-cache" ;;
esac
export ZEROREG_CACHE_DIR="${ZEROREG_CACHE_DIR:-$default_cache}"
ctest --test-dir "$build_dir" --output-on-failure -j2

bash scripts/check-install.sh

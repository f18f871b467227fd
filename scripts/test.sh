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
ctest --test-dir "$build_dir" --output-on-failure -j2

bash scripts/check-install.sh

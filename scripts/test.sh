#!/usr/bin/env bash
# The project's test command (README): install/build, fetch and verify the models, run the
# C++ tests and, when the Python bindings have tests, those too.
#
#   bash scripts/test.sh
set -euo pipefail

repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo_root"
build_dir="${ZEROREG_BUILD_DIR:-build}"

bash scripts/setup.sh
bash scripts/fetch-assets.sh
ctest --test-dir "$build_dir" --output-on-failure -j2

if [[ -d python/tests ]]; then
  ZEROREG_PYTHONPATH="$build_dir/python" /usr/bin/python3 -m pytest -q python/tests
else
  echo "test: no python/tests folder, skipping the Python tests"
fi

#!/usr/bin/env bash
# Installs the Debian packages zeroreg needs (only the missing ones) and builds it in build/.
#
#   bash scripts/setup.sh
#
# Safe to run repeatedly: apt-get runs only when a package is missing, and the build is
# incremental. Environment overrides: ZEROREG_BUILD_DIR (default build), ZEROREG_JOBS (default
# nproc).
set -euo pipefail

repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo_root"

# chromium: only for the test that opens `zeroreg report` pages headless (tests/viz/).
# python3-onnx: scripts/fetch-assets.sh rewrites the PicoDet export for OpenCV 4.6 with it.
packages=(
  cmake g++ make
  libopen3d-dev libopencv-dev libeigen3-dev nlohmann-json3-dev libcli11-dev libspdlog-dev
  googletest libgtest-dev
  pybind11-dev python3-dev python3-numpy python3-pytest python3-onnx
  clang-format
  chromium
)

missing=()
for pkg in "${packages[@]}"; do
  status="$(dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null || true)"
  [[ "$status" == "install ok installed" ]] || missing+=("$pkg")
done

if [[ ${#missing[@]} -gt 0 ]]; then
  echo "setup: installing ${missing[*]}"
  as_root=()
  if [[ "$(id -u)" -ne 0 ]]; then
    command -v sudo >/dev/null 2>&1 || {
      echo "setup: not root and sudo is not available; install as root: apt-get install ${missing[*]}" >&2
      exit 1
    }
    as_root=(sudo)
  fi
  "${as_root[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update
  "${as_root[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends \
    "${missing[@]}"
else
  echo "setup: all ${#packages[@]} packages already installed"
fi

build_dir="${ZEROREG_BUILD_DIR:-build}"
jobs="${ZEROREG_JOBS:-$(nproc)}"
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release
cmake --build "$build_dir" -j"$jobs"
echo "setup: built $repo_root/$build_dir/zeroreg"

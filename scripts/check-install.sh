#!/usr/bin/env bash
# Proves that zeroreg is usable from outside its build tree, on the existing build, and that the
# docs' commands run:
#  1. runs the code blocks of README's "Use it from your project" as written, in order (bash
#     blocks with bash, python blocks with the interpreter named on their first line): install
#     into build/install, build examples/ against it, install the Python package into a fresh
#     venv (build/venv) and register the demo pair from both;
#  2. checks that the example found the installed package, not the build tree, and that the
#     models were installed with both;
#  3. runs the Python tests with the venv's Python from outside the source tree, no PYTHONPATH;
#  4. registers the demo pair with the build-tree CLI and the installed CLI and compares the 4x4
#     T_target_source of all four results exactly, and their zeroreg_version with CMakeLists.txt;
#  5. runs every other command block of README.md and docs/*.md (```bash, ```sh, ```python) as
#     written, from the repository root with build/ on PATH, so that the docs cannot drift from
#     the program. A block that cannot run here (placeholders, hours of work, data or tools we do
#     not have) has `<!-- not run: why -->` on the line before it, and is listed as skipped. A
#     python block's first line names its interpreter (`# [VAR=value ...] /path/to/python`). An
#     untagged block that starts like a command is an error: tag it, or mark it.
#
#   bash scripts/check-install.sh      (scripts/test.sh runs it after the build-tree tests)
set -euo pipefail

repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo_root"
if [[ "${ZEROREG_BUILD_DIR:-build}" != build ]]; then
  echo "check-install: skipped, the README's commands use build/; only the Python tests run, on" \
    "the build tree's module ($ZEROREG_BUILD_DIR/python)"
  ZEROREG_PYTHONPATH="$ZEROREG_BUILD_DIR/python" /usr/bin/python3 -m pytest -q python/tests
  exit 0
fi
kitchen="../shared/data/7scenes-redkitchen"
out="build/check-install"
rm -rf build/install build/example build/venv "$out"
mkdir -p "$out"
start=$SECONDS

# 1. The README's blocks, extracted into files so that each runs exactly as written.
awk -v dir="$out" '
  /^## / { inside = ($0 == "## Use it from your project") }
  inside && /^```(bash|python)$/ { n++; lang = substr($0, 4); file = sprintf("%s/block-%d.%s", dir, n, lang); next }
  inside && /^```$/ && file != "" { close(file); file = ""; next }
  file != "" { print > file }
' README.md
blocks=("$out"/block-*)
[[ -e "${blocks[0]}" ]] || { echo "check-install: README has no blocks to run" >&2; exit 1; }
for block in "${blocks[@]}"; do
  echo "check-install: running README $(basename "$block")"
  case "$block" in
    *.bash) bash -euo pipefail "$block" ;;
    *.python)
      interpreter="$(sed -n '1s/^# *//p' "$block")"
      [[ -x "$interpreter" ]] || { echo "check-install: $block: first line must name the interpreter" >&2; exit 1; }
      "$interpreter" "$block" ;;
  esac
done

# 2. Where things came from.
example_pkg="$(sed -n 's/^zeroreg_DIR:PATH=//p' build/example/CMakeCache.txt)"
if [[ "$example_pkg" != "$repo_root/build/install/lib/cmake/zeroreg" ]]; then
  echo "check-install: the example used the package at '$example_pkg', not build/install" >&2
  exit 1
fi
for list in build/install/share/zeroreg/assets/assets.sha256 build/venv/share/zeroreg/assets/assets.sha256; do
  [[ -f "$list" ]] || { echo "check-install: $list missing: the models were not installed" >&2; exit 1; }
done
# The Open3D module (docs/INSTALL.md): the installed CLI and the venv's package load their own
# copies, not the build tree's.
cli_module="$(build/install/bin/zeroreg info | sed -n 's/^open3d module: \([^ ]*\) (loads.*/\1/p')"
if [[ "$cli_module" != "$repo_root/build/install/lib/zeroreg/libzeroreg-open3d.so" ]]; then
  echo "check-install: the installed CLI loads the Open3D module '$cli_module', not build/install's" >&2
  exit 1
fi
venv_module="$(cd /tmp && env -u PYTHONPATH -u ZEROREG_PYTHONPATH "$repo_root/build/venv/bin/python" \
  -c 'import zeroreg; print(zeroreg.open3d_module_path())')"
if [[ "$venv_module" != "$repo_root/build/venv/"*"/site-packages/zeroreg/libzeroreg-open3d.so" ]]; then
  echo "check-install: the venv's package loads the Open3D module '$venv_module', not its own" >&2
  exit 1
fi
echo "check-install: README blocks ran in $((SECONDS - start)) s"

# 3. The Python tests against the installed package, from a folder outside the repository.
outside="$(mktemp -d)"
trap 'rm -rf "$outside"' EXIT
(cd "$outside" && env -u PYTHONPATH -u ZEROREG_PYTHONPATH "$repo_root/build/venv/bin/python" \
  -m pytest -q -c "$repo_root/python/pytest.ini" "$repo_root/python/tests")

# 4. The same transform, bit for bit, from the build tree's CLI, the installed CLI (tuned and
#    untuned), the example and the venv. JSON numbers are written with 17 significant digits, so
#    they round-trip exactly.
build/zeroreg register --source "$kitchen@20" --target "$kitchen@0" --out "$out/cli.json" >/dev/null
build/install/bin/zeroreg register --source "$kitchen@20" --target "$kitchen@0" \
  --out "$out/installed-cli.json" >/dev/null
# zeroreg-core without glibc's malloc tunables (apps/tuned_environment.cpp): the same numbers.
ZEROREG_MALLOC_TUNING=off build/install/bin/zeroreg-core register --source "$kitchen@20" \
  --target "$kitchen@0" --out "$out/installed-untuned.json" >/dev/null
/usr/bin/python3 - "$out/cli.json" "$out/installed-cli.json" "$out/installed-untuned.json" \
  build/example/result.json \
  build/venv/result.json <<'EOF'
import json, re, sys

version = re.search(r"project\(zeroreg\s+VERSION\s+([0-9.]+)", open("CMakeLists.txt").read()).group(1)
results = {path: json.load(open(path))["result"] for path in sys.argv[1:]}
reference_path, reference = next(iter(results.items()))
for path, result in results.items():
    if result["T_target_source"] != reference["T_target_source"]:
        sys.exit(f"check-install: T_target_source of {path} differs from {reference_path}")
    if result["zeroreg_version"] != version:
        sys.exit(f"check-install: {path} says zeroreg_version {result['zeroreg_version']}, CMake {version}")
print(f"check-install: T_target_source identical in all {len(results)} results (zeroreg {version}):")
for row in reference["T_target_source"]:
    print("  " + " ".join(repr(x) for x in row))
EOF

# 5. Every other command block of README.md and docs/ (step 1 ran "Use it from your project").
docs_start=$SECONDS
docs_out="$out/docs"
mkdir -p "$docs_out"
awk -v dir="$docs_out" '
  FNR == 1 { section = ""; prev = "" }
  /^## / && !file { section = $0 }
  !file && /^```/ {
    lang = substr($0, 4)
    skip = (prev ~ /^<!-- not run: .* -->$/)
    first = 0
    if (lang ~ /^(bash|sh|python)$/ && !(FILENAME == "README.md" && section == "## Use it from your project")) {
      n++
      where = FILENAME ":" FNR
      if (skip) { print "skip\t" where "\t" prev > (dir "/manifest"); file = "/dev/null" }
      else { file = sprintf("%s/doc-%03d.%s", dir, n, lang == "sh" ? "bash" : lang); print "run\t" where "\t" file > (dir "/manifest") }
    } else if (lang == "") {
      file = "/dev/null"; untagged = FILENAME ":" FNR; first = 1
    } else { file = "/dev/null" }
    prev = $0; next
  }
  file && /^```$/ { if (file != "/dev/null") close(file); file = ""; prev = $0; next }
  file {
    if (first && $0 !~ /^[[:space:]]*$/) {
      first = 0
      if ($0 ~ /^(build\/|\.\/build\/|zeroreg (register|eval|fuse|info|report|bench-models) |bash |python3? |\/usr\/bin\/python3|PYTHONPATH=|ZEROREG_|cmake |METHODS=|JOBS=)/)
        print "untagged\t" untagged > (dir "/manifest")
    }
    if (file != "/dev/null") print > file
    next
  }
  { prev = $0 }
' README.md docs/*.md
if grep -q '^untagged' "$docs_out/manifest"; then
  echo "check-install: command blocks without a language tag (tag them bash, or mark them" \
    "<!-- not run: why -->):" >&2
  grep '^untagged' "$docs_out/manifest" | cut -f2 >&2
  exit 1
fi
while IFS=$'\t' read -r what where rest; do
  case "$what" in
    skip) echo "check-install: skipped $where ${rest#<!-- }" | sed 's/ -->$//' ;;
    run)
      block_start=$SECONDS
      case "$rest" in
        *.bash) PATH="$repo_root/build:$PATH" bash -euo pipefail "$rest" </dev/null >"$rest.log" 2>&1 ;;
        *.python)
          read -ra interpreter <<<"$(sed -n '1s/^# *//p' "$rest")"
          [[ ${#interpreter[@]} -gt 0 ]] || { echo "check-install: $where: a python block's first line must name the interpreter" >&2; exit 1; }
          env "${interpreter[@]}" "$rest" </dev/null >"$rest.log" 2>&1 ;;
      esac || { echo "check-install: $where failed:" >&2; tail -n 30 "$rest.log" >&2; exit 1; }
      echo "check-install: ran $where in $((SECONDS - block_start)) s" ;;
  esac
done <"$docs_out/manifest"
echo "check-install: doc blocks: $(grep -c '^run' "$docs_out/manifest") ran," \
  "$(grep -c '^skip' "$docs_out/manifest") marked not run, in $((SECONDS - docs_start)) s"
echo "check-install: passed in $((SECONDS - start)) s"

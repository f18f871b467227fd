#!/usr/bin/env bash
# Runs the libFuzzer harnesses of fuzz/ (all, or those named) for a bounded time (fuzz/README.md). Not part of the
# default CI (scripts/test.sh): building the instrumented library takes a while.
#
#   bash scripts/fuzz.sh [SECONDS_PER_HARNESS [HARNESS...]]     (default 60 s, every harness)
#
# Environment: ZEROREG_FUZZ_BUILD_DIR (default build-fuzz), ZEROREG_JOBS (build jobs, default 2).
# Exit status 1 if a harness found a crash; its input is left in <build>/findings/<harness>/.
set -euo pipefail

repo_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$repo_root"
seconds="${1:-60}"
build_dir="${ZEROREG_FUZZ_BUILD_DIR:-build-fuzz}"
jobs="${ZEROREG_JOBS:-2}"

command -v clang++ >/dev/null || {
  echo "fuzz: clang++ not found; install the Debian packages clang and libclang-rt-dev" >&2
  exit 2
}
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang \
  -DCMAKE_CXX_COMPILER=clang++ -DZEROREG_FUZZ=ON -DZEROREG_BUILD_TESTS=OFF \
  -DZEROREG_BUILD_PYTHON=OFF -DZEROREG_WERROR=OFF >/dev/null
harnesses=("${@:2}")
if [[ ${#harnesses[@]} -eq 0 ]]; then
  for source in fuzz/fuzz_*.cpp; do harnesses+=("$(basename "$source" .cpp)"); done
fi
for harness in "${harnesses[@]}"; do
  [[ -f "fuzz/$harness.cpp" ]] || { echo "fuzz: no harness fuzz/$harness.cpp" >&2; exit 2; }
done
cmake --build "$build_dir" -j"$jobs" --target "${harnesses[@]}"

status=0
for harness in "${harnesses[@]}"; do
  corpus="$build_dir/corpus/$harness"
  findings="$build_dir/findings/$harness"
  mkdir -p "$corpus" "$findings"
  cp -n fuzz/corpus/"$harness"/* "$corpus"/ 2>/dev/null || true
  echo "fuzz: $harness for ${seconds}s"
  # Seeds are copied so the growing corpus stays in the build folder; -rss_limit_mb keeps a
  # runaway allocation a finding instead of a swapping machine.
  if ! "$build_dir/$harness" "$corpus" -max_total_time="$seconds" -rss_limit_mb=2048 \
      -timeout=10 -artifact_prefix="$findings/" -print_final_stats=1 \
      >"$findings/log.txt" 2>&1; then
    echo "fuzz: $harness FOUND A CRASH; see $findings/log.txt" >&2
    status=1
  else
    grep -E "^stat::number_of_executed_units|^#[0-9]+.*DONE" "$findings/log.txt" | tail -2 || true
  fi
done
exit $status

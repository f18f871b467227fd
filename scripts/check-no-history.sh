#!/usr/bin/env bash
# Fails when a tracked file other than CHANGELOG.md tells how the work was organised: a numbered
# work session ("the twelfth ...", "the 3rd ...", "this / previous ...") or "since issue N". Code
# comments say why, docs the current state; history belongs in CHANGELOG.md. Run by ctest
# (NoHistoryInTrackedFiles) and by hand:
#
#   bash scripts/check-no-history.sh [REPO_DIR]
#
# Outside a git checkout (a source tarball) there is nothing tracked to check: it says so and
# passes.
set -euo pipefail

repo="${1:-$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)}"
if ! git -C "$repo" rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  echo "check-no-history: skipped, $repo is not a git checkout"
  exit 0
fi

# The word is split so that this file does not match its own pattern.
word="ses""sion"
ordinals="fourth|fifth|sixth|seventh|eighth|ninth|tenth|eleventh|twelfth|[a-z]+teenth|twentieth"
ordinals+="|twenty-[a-z]+|thirtieth|thirty-[a-z]+|[0-9]+(st|nd|rd|th)"
pattern="(${ordinals}) ${word}|since issue [0-9]+"
# "second", "third", "this" and "previous" count only in the work-log sense (after "the", "this"
# or an opening parenthesis or comma, as in a label): recordings made on several occasions are
# what `zeroreg merge` is about ("a second one may be darker"), and stay free to name.
relative="(this|previous|the (second|third)|[(,] ?(second|third)) ${word}"

matches="$(git -C "$repo" grep -n -I -i -E -e "$pattern" -e "$relative" -- . ':(exclude)CHANGELOG.md' \
  || true)"
if [[ -n "$matches" ]]; then
  echo "check-no-history: history outside CHANGELOG.md (say why, not when; see CHANGELOG.md):" >&2
  echo "$matches" >&2
  exit 1
fi
echo "check-no-history: no work-log words in tracked files"

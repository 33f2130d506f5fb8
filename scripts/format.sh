#!/usr/bin/env bash
# Formats incise's C++ sources with the project's .clang-format (clang-format 14, Debian's clang-format):
#   scripts/format.sh           rewrites every tracked .cpp / .h in place
#   scripts/format.sh --check   changes nothing; lists the files that are not formatted and exits 1 if any
# Exit 77 (CTest: skipped) when clang-format is not installed (scripts/install-deps.sh installs it).
set -euo pipefail
cd "$(dirname "$0")/.."
if ! command -v clang-format > /dev/null; then
  echo "format: clang-format is not installed (apt-get install clang-format)"
  exit 77
fi
mapfile -t files < <(git ls-files '*.cpp' '*.h')
if [ "${1:-}" = "--check" ]; then
  bad=0
  for f in "${files[@]}"; do
    if ! clang-format --dry-run --Werror "$f" > /dev/null 2>&1; then echo "not formatted: $f"; bad=1; fi
  done
  [ "$bad" = 0 ] && echo "format: ${#files[@]} files formatted as .clang-format says"
  exit $bad
fi
clang-format -i "${files[@]}"

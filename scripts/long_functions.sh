#!/usr/bin/env bash
# Lists functions longer than N lines (default 80) and files longer than M lines (default 600) in the
# library, the apps and the benchmarks' support code, so the size limits of the code can be checked:
#   scripts/long_functions.sh [N] [M]
# Uses universal-ctags (Debian's universal-ctags) for the functions' extents. Tests and benchmark
# tables are left out. Prints nothing and exits 0 when every limit holds; exits 1 otherwise (77 without ctags).
set -euo pipefail
cd "$(dirname "$0")/.."
if ! ctags --version 2> /dev/null | grep -q "Universal Ctags"; then
  echo "long_functions: universal-ctags is not installed (apt-get install universal-ctags)"
  exit 77
fi
max_function=${1:-80}
max_file=${2:-600}
files=$(git ls-files 'measure/*.cpp' 'measure/*.h' 'cutting/*.cpp' 'cutting/*.h' 'devices/*.cpp' 'devices/*.h' 'sim/*.cpp' 'sim/*.h' \
  'viewer/*.cpp' 'viewer/*.h' 'apps/*.cpp' 'apps/*.h' 'jobs/*.cpp' 'jobs/*.h' 'capi/*.cpp' 'capi/*.h' \
  'python/*.cpp' 'python/*.h')
status=0
for f in $files; do
  lines=$(wc -l < "$f")
  if [ "$lines" -gt "$max_file" ]; then echo "file $f: $lines lines"; status=1; fi
done
# shellcheck disable=SC2086
while IFS='|' read -r name line file end; do
  len=$((end - line + 1))
  if [ "$len" -gt "$max_function" ]; then echo "function $file:$line $name: $len lines"; status=1; fi
done < <(ctags -x --_xformat='%N|%n|%F|%{end}' --kinds-C++=f --fields=+e --extras=-q $files 2>/dev/null |
         awk -F'|' '$4 != ""')
exit $status

#!/usr/bin/env bash
# Long commands show progress on stderr when it is a terminal, and only then: `replay --fast`, `cut` and
# `bench` run once under a pseudo-terminal (util-linux `script`) and once with stderr to a file.
#   progress_test.sh INCISE SCENARIOS_DIR
set -euo pipefail
incise=$(realpath "$1")
scenarios=$(realpath "$2")
work=$(mktemp -d /tmp/incise-progress-test.XXXXXX)
trap 'rm -rf "$work"' EXIT
cd "$work"

on_terminal() {  # the command's terminal output, carriage returns as newlines
  script -qec "$*" /dev/null | tr '\r' '\n'
}
expect_bar() {  # a drawn bar ends at 100% with the label given
  grep -q "^$1 \[#\{40\}\] 100%" || { echo "no finished progress bar labelled '$1'"; exit 1; }
}

on_terminal "$incise replay --fast --out replay" | expect_bar "replay bunny-straight"
on_terminal "$incise cut --out cut" | expect_bar "cut"
on_terminal "$incise wrap $scenarios/wrap/sphere-cylinder.json --out wrap" | expect_bar "wrap sphere-cylinder"
on_terminal "$incise bench --seconds 0.5" > bench.txt
for name in bunny-straight bunny-curved bunny-crossing; do expect_bar "bench $name" < bench.txt; done

"$incise" replay --fast --out replay > /dev/null 2> replay.err
"$incise" cut --out cut > /dev/null 2> cut.err
"$incise" wrap "$scenarios/wrap/sphere-cylinder.json" --out wrap > /dev/null 2> wrap.err
if grep -q '\[#' replay.err cut.err wrap.err; then echo "a progress bar was written to a file"; exit 1; fi
echo "progress_test: bars on a terminal, none into files"

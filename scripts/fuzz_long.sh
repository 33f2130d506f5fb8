#!/usr/bin/env bash
# The long fuzz run: each harness in turn (one at a time, under nice -n 19, so the machine stays usable) for
# 10,000,000 executions or a time limit per harness, whichever comes first; prints executions, executions
# per second and wall time per harness (docs/reliability.md, "Fuzzing", has the figures of runs). Exits 1 on any
# finding, as scripts/fuzz.sh does (the inputs in build-fuzz/fuzz-artifacts/).
#   scripts/fuzz_long.sh [--seconds S] [--runs N] [--no-build] [HARNESS...]   (default 3600 s, 10^7 runs, all)
set -euo pipefail
cd "$(dirname "$0")/.."
exec scripts/fuzz.sh --seconds 3600 --runs 10000000 --jobs 1 --nice "$@"

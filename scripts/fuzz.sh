#!/usr/bin/env bash
# Builds incise's libFuzzer harnesses (tests/fuzz/: clang 14, ASan + UBSan) in build-fuzz/ and runs each of
# them for a while; prints per harness the executions, executions per second, wall time and the outcome.
# Exits 1 if any harness found a crash, a leak, a sanitizer report, a timeout or an out-of-memory (the input
# that did it is in build-fuzz/fuzz-artifacts/<harness>/), 0 otherwise.
#   scripts/fuzz.sh [--seconds S] [--runs N] [--jobs J] [--nice] [--no-build] [--opt FLAGS] [--build-jobs N]
#                   [HARNESS...]
#     --seconds S  time limit per harness (default 30); --runs N  also stop after N executions (default: none)
#     --jobs J     harnesses run J at a time (default 1); --nice  under nice -n 19
#     --no-build   run the harnesses already in build-fuzz/ (while another build of it is under way)
#     --opt FLAGS  the compiler's optimisation flags (default "-O1 -g1"; scripts/test.sh builds with "-O1 -g0":
#                  a cold build of all nine takes under 3 min on 2 cores, the CGAL files at -O0 whatever FLAGS)
#     --build-jobs N  the build's parallel jobs (default: every core; 1 leaves a core to others)
#     HARNESS      a subset (fuzz_trace_csv ...), only those built; default all nine
# scripts/test.sh runs it with --seconds 30 --jobs 2; scripts/fuzz_long.sh is the long run. The corpus each
# harness grows is kept in build-fuzz/fuzz-corpus/<harness>/ (the seeds, tests/fuzz/corpus/, are only read).
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=30 runs=-1 jobs=1 nice_cmd=() harnesses=() build_step=1 opt="-O1 -g1" build_jobs=$(nproc)
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) seconds=$2; shift 2 ;;
    --runs) runs=$2; shift 2 ;;
    --jobs) jobs=$2; shift 2 ;;
    --nice) nice_cmd=(nice -n 19); shift ;;
    --no-build) build_step=0; shift ;;
    --opt) opt=$2; shift 2 ;;
    --build-jobs) build_jobs=$2; shift 2 ;;
    *) harnesses+=("$1"); shift ;;
  esac
done
# Named harnesses: only their targets are built (a cold -O1 build of all nine is the longer wait).
targets=(incise_fuzzers)
[ ${#harnesses[@]} -eq 0 ] || targets=("${harnesses[@]}")
# fuzz_cut_stroke (the cutter's outputs) runs last: at -O1 under ASan one stroke takes about 1 s.
[ ${#harnesses[@]} -gt 0 ] || harnesses=(fuzz_trace_csv fuzz_scenario fuzz_wrap_scenario fuzz_surface_mesh
  fuzz_hid_descriptor fuzz_hid_report fuzz_hid_recording fuzz_hid_profile fuzz_cut_stroke)

build=build-fuzz
start=$(date +%s)
# The harnesses write each input to a scratch file (tests/fuzz/fuzz_input.h, under TMPDIR): on a disk, the
# file system's flush at close was most of the file-based harnesses' time (3,000 exec/s for the trace
# reader on /tmp here, 6,750 on tmpfs), so the scratch goes to /dev/shm where there is one.
if [ -z "${TMPDIR:-}" ] && [ -d /dev/shm ] && [ -w /dev/shm ]; then export TMPDIR=/dev/shm; fi
# A unity build, as scripts/test.sh's sanitizer builds: a target's sources are compiled 8 to a unit.
if [ "$build_step" = 1 ]; then
  cmake -S . -B "$build" -G Ninja -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=$opt -DNDEBUG" -DINCISE_SANITIZE=ON -DINCISE_FUZZ=ON \
    -DINCISE_BUILD_TESTS=OFF -DINCISE_BUILD_BENCH=OFF -DCMAKE_UNITY_BUILD=ON > /dev/null
  cmake --build "$build" -j "$build_jobs" --target "${targets[@]}"
  echo "fuzz: harnesses built in $(($(date +%s) - start)) s"
fi

# One harness: its own grown corpus first (new inputs go there), then the seeds; the log in fuzz-logs/.
run_one() {
  local h=$1 t0 status=0
  mkdir -p "$build/fuzz-corpus/$h" "$build/fuzz-artifacts/$h" "$build/fuzz-logs"
  local dict=() log="$build/fuzz-logs/$h.log"
  [ -f "tests/fuzz/dict/$h.dict" ] && dict=(-dict="tests/fuzz/dict/$h.dict")
  # The trace reader's grammar is per line and what it carries across lines (the header, the comment block
  # after it, the previous sample's time) needs only a few: 1 KB holds the header and five full-precision
  # samples. At libFuzzer's default 4 KB a fuzzed trace is mostly bad lines, one TraceError each, and under
  # ASan the unwinding and the allocator made it 700-3,000 exec/s (tests/fuzz/fuzz_trace_csv.cpp).
  [ "$h" = fuzz_trace_csv ] && dict+=(-max_len=1024)
  t0=$(date +%s%N)
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    "${nice_cmd[@]}" "$build/tests/fuzz/$h" -max_total_time="$seconds" -runs="$runs" -timeout=30 \
    -rss_limit_mb=2048 -malloc_limit_mb=2048 -print_final_stats=1 "${dict[@]}" \
    -artifact_prefix="$build/fuzz-artifacts/$h/" "$build/fuzz-corpus/$h" "tests/fuzz/corpus/$h" > "$log" 2>&1 ||
    status=$?
  local wall execs rate outcome=ok
  wall=$((($(date +%s%N) - t0) / 1000000))
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  if [ "$status" != 0 ]; then outcome="FAILED (exit $status, see $log)"; fi
  printf '%-20s execs %12s  exec/s %7s  wall %4d.%01d s  %s\n' "$h" "${execs:-?}" "${rate:-?}" \
    $((wall / 1000)) $((wall % 1000 / 100)) "$outcome"
  [ "$status" = 0 ]
}

failed=0
running=0
for h in "${harnesses[@]}"; do
  run_one "$h" &
  running=$((running + 1))
  if [ "$running" -ge "$jobs" ]; then
    wait -n || failed=1
    running=$((running - 1))
  fi
done
while [ "$running" -gt 0 ]; do
  wait -n || failed=1
  running=$((running - 1))
done
echo "fuzz: ${#harnesses[@]} harnesses in $(($(date +%s) - start)) s (build included)"
if [ "$failed" != 0 ]; then
  echo "fuzz: FAILED (the inputs are in $build/fuzz-artifacts/)"
  exit 1
fi

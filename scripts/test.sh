#!/usr/bin/env bash
# The whole test suite, from a fresh clone on Debian 12: installs what is missing, builds (Release),
# runs every test, then builds again with AddressSanitizer + UndefinedBehaviorSanitizer and runs the
# suite under them, then builds the libFuzzer harnesses (clang 14) and runs each for 30 s. Exits non-zero if
# anything fails. Benchmarks are built but not run. The Release pass includes the C API's C program, the
# Python module's pytest suite, the examples built and run against an installed prefix, and the API
# reference (Doxygen, any warning an error); the C API's program runs again under the sanitizers.
#   scripts/test.sh            everything
#   scripts/test.sh --quick    the Release pass only, without [slow] cases
set -euo pipefail
cd "$(dirname "$0")/.."

quick=0
[ "${1:-}" = "--quick" ] && quick=1

scripts/install-deps.sh
jobs=$(nproc)
# The sanitizer builds: -O1 with line tables only (enough for file:line in every report) compiles in about
# half the time of RelWithDebInfo's -O2 -g (measured on cutting/incision/src/surface_cutter.cpp under ASan: 15 s
# against 32 s), which is most of this script's time on a 2-core machine. They are unity builds (CMake
# compiles up to 8 sources of a target as one): each header is parsed once per batch, not once per source
# (four sim test files under ASan: 73 s apart, 49 s as one). The Release build compiles the libraries one
# source at a time, as users build them, so a source that compiles only because another one included what
# it needs fails there; its tests are unity builds (INCISE_UNITY_TESTS).
sanitizer_flags=(-DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG"
  -DINCISE_BUILD_BENCH=OFF -DCMAKE_UNITY_BUILD=ON)

echo "== Release build and tests"
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DINCISE_UNITY_TESTS=ON
cmake --build build -j "$jobs"
if [ "$quick" = 1 ]; then
  ctest --test-dir build --output-on-failure -j "$jobs" -LE slow
  exit 0
fi
# Every test runs once: a test that fails fails the script (a flaky test is a bug to fix, never one to rerun).
# Tests labelled "long" (the kill test's 100 seeds: 200 s) are left to a manual run (ctest -L long) to keep
# the whole script near 45 minutes on 2 cores.
ctest --test-dir build --output-on-failure -j "$jobs" -LE long

echo "== ThreadSanitizer build: the threaded tests (queue, triple buffer, loop, snapshots read while the loop runs,"
echo "   the geometry stream followed by a reader thread, the HID device thread with hot-plug, alone and feeding the loop)"
cmake -S . -B build-tsan -G Ninja "${sanitizer_flags[@]}" -DINCISE_TSAN=ON
cmake --build build-tsan -j "$jobs" --target incise_tests_sim incise_tests_devices
TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1 \
  ./build-tsan/tests/sim/incise_tests_sim "[threads],spsc_queue*,triple_buffer*,fixed_rate_loop*"
TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1 ./build-tsan/tests/devices/incise_tests_devices "[threads]"

# The "gl" tests (pictures through Mesa, under xvfb-run and EGL) ran in the Release pass above; Mesa's and
# X's own allocations would read as leaks under LeakSanitizer, so the sanitizer pass leaves them out, and
# the kill test too ("kill": the CLI's files under SIGKILL, compared with an unkilled run's, which the
# live recorder's timing under ASan does not reproduce; it ran in the Release pass).
echo "== AddressSanitizer + UndefinedBehaviorSanitizer build and tests"
cmake -S . -B build-asan -G Ninja "${sanitizer_flags[@]}" -DINCISE_SANITIZE=ON
cmake --build build-asan -j "$jobs"
# One test is left to the Release pass: the straight trace through the tet bunny, fast against real time,
# differs in the last bit of 13 of 17,031 nodes in this -O1 build (1.4e-17 m; the same bits in Release, and
# the crossing trace's test under load gives the same bits in both builds). CHANGELOG.md, known limitations.
# The style and docs checks run no compiled code: the Release pass ran them. Tests labelled "release" (three
# of the CLI's shell tests, whose code the sanitizers see in other tests: tests/CMakeLists.txt) ran there too.
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build-asan --output-on-failure -j "$jobs" -LE 'slow|gl|kill|release' \
  -E '^(style|docs):|sim:replay: a tet tissue is cut, the same bits fast and in real time'

# Every parser's libFuzzer harness (tests/fuzz/) for 30 s, two at a time, under ASan + UBSan: a crash, leak,
# sanitizer report, timeout or out-of-memory fails the script (scripts/fuzz_long.sh is the long run).
echo "== Fuzzing: each libFuzzer harness for 30 s (clang 14, ASan + UBSan), two at a time"
scripts/fuzz.sh --seconds 30 --jobs 2 --opt "-O1 -g0"

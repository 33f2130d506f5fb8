#!/usr/bin/env bash
# The main job, from a fresh clone on Debian 12: installs what is missing, builds (Release) and runs
# incise's most complete capability. Today that is the B-spline engine's re-deformation benchmark
# (prints JSON); it becomes `incise replay` on the default scenario when the simulation loop lands.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build build -j "$(nproc)" --target incise_bench_volume
./build/bench/incise_bench_volume

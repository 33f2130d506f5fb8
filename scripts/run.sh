#!/usr/bin/env bash
# The main job, from a fresh clone on Debian 12: installs what is missing, builds (Release) and runs
# `incise replay` on the default scenario (a 5 cm incision over the bunny's back, replayed through the
# 1 kHz simulation loop in real time). Extra arguments go to `incise replay` (e.g. a scenario, --fast).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build build -j "$(nproc)" --target incise
exec ./build/apps/incise replay --realtime --out out/replay "$@"

#!/usr/bin/env bash
# Regenerates the recorded traces shipped in scenarios/traces/ from their generator scenarios in
# scenarios/generate/ (strokes over the bunny and the skin pad, poses at 1 kHz; see sim/include/incise/sim/stroke_poses.h).
# The output is deterministic: running this again gives the same bytes (a test checks one of them).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build build --target incise
for name in bunny-straight bunny-curved bunny-crossing pad-straight pad-s-curve bunny-back; do
  ./build/apps/incise record "scenarios/generate/$name.json" --out "scenarios/traces/$name.csv"
done

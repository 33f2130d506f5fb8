#!/usr/bin/env bash
# Regenerates the HID recordings shipped in scenarios/hid/ from their scenarios' "synthesis" blocks (the
# strokes of scenarios/generate/ and scenarios/hid/calibrate/presses.json, through the real descriptors in
# scenarios/hid/descriptors/; see devices/include/incise/devices/hid_synth.h). Deterministic: running this again
# gives the same bytes (tests/apps/hid_cli_test.sh checks the three bunny ones and the calibration presses).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build build --target incise
for name in bunny-pen-wacom bunny-pen-xppen bunny-spacenavigator pad-pen-wacom; do
  ./build/apps/incise hid synth "scenarios/$name.json"
done
./build/apps/incise hid synth scenarios/hid/calibrate/pen-wacom.json

#!/usr/bin/env bash
# Runs capi_test (the C API from C99) and compares what it made with the CLI's: the geometry hash of the
# scenario stepped frame by frame through incise_world_step with `incise replay --fast`'s, the tensioned
# pad's vertices as simulated with replay's cut.obj, and the score line of incise_score_trace with the first
# line `incise score` prints.
#   capi_test.sh CAPI_TEST INCISE SCENARIOS_DIR
set -euo pipefail
capi_test=$1
incise=$2
scenarios=$3
work=$(mktemp -d /tmp/incise-capi-test.XXXXXX)
trap 'rm -rf "$work"' EXIT

"$capi_test" "$scenarios" "$work"
"$incise" replay "$scenarios/pad-straight.json" --fast --out "$work/replay" > /dev/null
replay_hash=$(grep -o '"geometry_hash": *"[0-9a-f]*"' "$work/replay/report.json" | grep -o '[0-9a-f]\{16\}')
step_hash=$(cat "$work/step_hash.txt")
if [ "$replay_hash" != "$step_hash" ]; then
  echo "FAIL - stepped through the C API: geometry $step_hash; incise replay --fast: $replay_hash"
  exit 1
fi
echo "ok - stepped through the C API, the geometry incise replay --fast makes ($step_hash)"
"$incise" replay "$scenarios/pad-tension.json" --fast --out "$work/tension" > /dev/null
if ! cmp -s <(grep '^v ' "$work/tension/cut.obj" | cut -c3-) "$work/simulated_xyz.txt"; then
  echo "FAIL - incise_world_get_simulated_vertices of the stepped tensioned pad differ from incise replay --fast's cut.obj"
  exit 1
fi
echo "ok - the tensioned pad's vertices as simulated through the C API are replay's cut.obj, bit for bit"
"$incise" score "$scenarios/pad-straight.json" "$scenarios/traces/pad-straight.csv" 2> /dev/null | head -1 > "$work/cli_line.json"
if ! cmp -s <(tr -d '\n' < "$work/cli_line.json") "$work/score_line.json"; then
  echo "FAIL - incise_score_trace's line differs from incise score's:"
  diff <(tr -d '\n' < "$work/cli_line.json") "$work/score_line.json" || true
  exit 1
fi
echo "ok - incise_score_trace's JSON line is the one incise score prints, byte for byte"

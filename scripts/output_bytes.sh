#!/usr/bin/env bash
# The bytes incise makes, for checking that a change which should not change geometry does not: replays
# every shipped replay scenario (fast; the bunny-tets one too), cuts the default stroke and wraps every
# shipped wrap scenario, then prints one line per output file — its SHA-256 and its name — plus each
# replay's geometry hash. Run it before and after a change and compare the two listings:
#   scripts/output_bytes.sh build/apps/incise /tmp/before > before.txt
#   ... change, rebuild ...
#   scripts/output_bytes.sh build/apps/incise /tmp/after > after.txt && diff before.txt after.txt
# Reports and summaries (timings, paths) and frames.jsonl (which carries per-frame times) are left out: they differ by design.
set -euo pipefail
incise=$(realpath "$1")
work=${2:-$(mktemp -d)}
cd "$(dirname "$0")/.."
mkdir -p "$work"
for scenario in scenarios/*.json; do
  name=$(basename "$scenario" .json)
  "$incise" replay "$scenario" --fast --out "$work/replay-$name" > /dev/null
  echo "geometry_hash $(grep -o '"geometry_hash": *"[0-9a-f]*"' "$work/replay-$name/report.json" | grep -o '[0-9a-f]\{16\}') replay-$name"
done
"$incise" cut --out "$work/cut" > /dev/null || true
for scenario in scenarios/wrap/*.json; do
  name=$(basename "$scenario" .json)
  "$incise" wrap "$scenario" --out "$work/wrap-$name" > /dev/null 2>&1 || echo "exit $? wrap-$name"
done
(cd "$work" && find . -type f ! -name report.json ! -name summary.json ! -name frames.jsonl ! -name '*.tmp' | LC_ALL=C sort | xargs sha256sum)

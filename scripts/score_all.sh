#!/usr/bin/env bash
# Scores every trace (*.csv) under DIR against SCENARIO with `incise score`, in parallel with GNU parallel
# (Debian's `parallel`; scripts/install-deps.sh installs it): one job per batch of traces, as many jobs at a
# time as there are cores (or --jobs N). Writes OUT (default DIR/scores.jsonl): one JSON line per trace, in
# the traces' sorted order, then one summary line over all of them (the same keys as `incise score`'s).
#   scripts/score_all.sh DIR SCENARIO [--out OUT] [--jobs N] [--batch B]
# INCISE names the incise binary (default: incise on the PATH, else build/apps/incise beside this script).
# A trace that `incise score` refuses stops the run (exit 2, its message on stderr) and OUT is not written.
# The same run on a Slurm cluster, one array task per slice of the list: scripts/score_all.slurm.
set -euo pipefail
usage() { echo "usage: $0 DIR SCENARIO [--out OUT] [--jobs N] [--batch B]" >&2; exit 2; }
[ $# -ge 2 ] || usage
dir=$1 scenario=$2; shift 2
out="$dir/scores.jsonl" jobs=0 batch=20
while [ $# -gt 0 ]; do
  case $1 in
    --out) out=$2; shift 2 ;;
    --jobs) jobs=$2; shift 2 ;;
    --batch) batch=$2; shift 2 ;;
    *) usage ;;
  esac
done
[ -d "$dir" ] || { echo "score_all: $dir is not a folder" >&2; exit 2; }
[ -f "$scenario" ] || { echo "score_all: $scenario does not exist" >&2; exit 2; }
command -v parallel > /dev/null || { echo "score_all: GNU parallel is not installed (apt-get install parallel)" >&2; exit 2; }
incise=${INCISE:-$(command -v incise || echo "$(dirname "$0")/../build/apps/incise")}
[ -x "$incise" ] || { echo "score_all: no incise binary ($incise); set INCISE" >&2; exit 2; }

parts=$(mktemp -d)
trap 'rm -rf "$parts"' EXIT
find "$dir" -name '*.csv' -type f | LC_ALL=C sort > "$parts/list"
count=$(wc -l < "$parts/list")
[ "$count" -gt 0 ] || { echo "score_all: no *.csv trace under $dir" >&2; exit 2; }
# Batch k writes $parts/k.jsonl; --keep-order is not needed: the batches are joined in their order below.
parallel --will-cite --halt now,fail=1 --jobs "${jobs/#0/100%}" -N "$batch" --arg-file "$parts/list" \
  "\"$incise\" score \"$scenario\" {} --out \"$parts/{#}.jsonl\" > /dev/null"
for k in $(seq 1 $(( (count + batch - 1) / batch ))); do grep -v '^{"summary"' "$parts/$k.jsonl"; done > "$parts/lines"
python3 "$(dirname "$0")/score_summary.py" < "$parts/lines" > "$parts/summary"
cat "$parts/lines" "$parts/summary" > "$out.tmp" && mv "$out.tmp" "$out"
echo "score_all: $count trace(s) scored into $out"

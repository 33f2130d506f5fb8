#!/usr/bin/env python3
"""Reads `incise score` trace lines (JSON, one per line) on stdin and prints the summary line over all of
them, as `incise score` does for its own traces: the mean of each headline figure over the traces that have
it (scripts/score_all.sh, scripts/score_all.slurm)."""
import json
import sys

KEYS = ["time_s", "path_length_in_contact_m", "economy", "strokes_count", "idle_time_s", "peak_force_N"]
PLAN_KEYS = ["lateral_mean_abs_m", "share_within_lateral_tolerance", "share_uncut", "depth_mean_abs_error_m",
             "share_within_depth_tolerance"]

lines = [json.loads(l) for l in sys.stdin if l.strip() and not l.startswith('{"summary"')]
mean = {}
for key, block in [(k, None) for k in KEYS] + [(k, "plan") for k in PLAN_KEYS]:
    values = [(l[block] or {}).get(key) if block else l.get(key) for l in lines]
    values = [v for v in values if isinstance(v, (int, float))]
    if values:
        mean[(block + "." if block else "") + key] = sum(values) / len(values)
print(json.dumps({"summary": {"traces": len(lines), "mean": mean}}, separators=(",", ":")))

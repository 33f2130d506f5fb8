#!/usr/bin/python3
"""Scores every trace (*.csv) in a folder against a scenario, as `incise score` does, and prints a table;
also writes the table as CSV. Traces recorded on another tissue are refused, naming the file.

    python3 score_folder.py SCENARIO.json FOLDER [--csv scores.csv]
e.g. python3 score_folder.py "$(python3 -c 'import incise; print(incise.shipped("pad-straight.json"))')" traces/
"""
import argparse
import csv
import pathlib
import sys

import incise

COLUMNS = [  # (heading, key path in the score's dict, scale, format)
    ("trace", ("trace",), None, "{}"),
    ("time s", ("time_s",), 1, "{:.2f}"),
    ("path mm", ("path_length_in_contact_m",), 1e3, "{:.1f}"),
    ("economy", ("economy",), 1, "{:.2f}"),
    ("peak N", ("peak_force_N",), 1, "{:.2f}"),
    ("lateral mm", ("plan", "lateral_mean_abs_m"), 1e3, "{:.2f}"),
    ("in band", ("plan", "share_within_lateral_tolerance"), 1, "{:.0%}"),
    ("depth err mm", ("plan", "depth_mean_abs_error_m"), 1e3, "{:.2f}"),
    ("SPARC", ("session", "sparc"), 1, "{:.2f}"),
]


def cell(line, path, scale, form):
    value = line
    for key in path:
        value = value.get(key) if isinstance(value, dict) else None
    if value is None:
        return "-"
    if path == ("trace",):
        return pathlib.Path(value).name
    return form.format(value * scale)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenario")
    parser.add_argument("folder")
    parser.add_argument("--csv", default="scores.csv")
    args = parser.parse_args()
    traces = sorted(str(p) for p in pathlib.Path(args.folder).glob("*.csv"))
    if not traces:
        sys.exit(f"score_folder: no *.csv in {args.folder}")
    try:
        lines = incise.score(args.scenario, traces)
    except (incise.InputError, ValueError) as error:
        sys.exit(f"score_folder: {error}")
    rows = [[cell(line, path, scale, form) for _, path, scale, form in COLUMNS] for line in lines]
    headings = [heading for heading, *_ in COLUMNS]
    widths = [max(len(h), *(len(r[i]) for r in rows)) for i, h in enumerate(headings)]
    print("  ".join(h.ljust(w) for h, w in zip(headings, widths)))
    for row in rows:
        print("  ".join(c.ljust(w) for c, w in zip(row, widths)))
    mean = incise.score_summary(lines)["summary"]["mean"]
    print(f"mean over {len(lines)} traces: economy {mean['economy']:.2f}, peak force {mean['peak_force_N']:.2f} N")
    with open(args.csv, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(headings)
        writer.writerows(rows)
    print(f"wrote {args.csv}")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Cuts a closed mesh along random strokes with `incise cut` and prints, per cut, what its summary.json says:
the pairs of faces that cross (mesh.self_intersections), the shortfall, the stroke's length in contact and
whether the blade went through. The reliability checks on scans nobody here chose (docs/reliability.md,
"Self-intersection") are drawn with it.

    scripts/random_cuts.py MESH [--incise build/apps/incise] [--scale 0.1] [--strokes 60] [--seed 20261207]
                          [--subdivide 0 2] [--out /tmp/random_cuts]

Each stroke starts 6 cm above the origin's plane (rays go down -y) at x, z uniform within 3 and 2.5 cm of
the axis, runs in a uniform direction in the x-z plane for 10-30 mm with the blade 2-4 mm deep (one draw
per stroke, in that order, from Python's random.Random(seed)), and is cut once per --subdivide value. A
stroke whose first ray misses the mesh is `incise cut`'s error (exit 2): listed as "no contact". The last
line sums the cuts in contact, those with crossing faces and their pairs. Exits 0 (a report, not a check)."""
import argparse
import json
import math
import os
import random
import subprocess
import sys


def draw(rng):
    x, z = rng.uniform(-0.03, 0.03), rng.uniform(-0.025, 0.025)
    angle = rng.uniform(0.0, 2.0 * math.pi)
    return x, z, math.cos(angle), math.sin(angle), rng.uniform(0.01, 0.03), rng.uniform(0.002, 0.004)


def cut(args, index, subdivide, stroke):
    x, z, dx, dz, length, depth = stroke
    out = os.path.join(args.out, f"{index}_{subdivide}")
    command = [args.incise, "cut", "--mesh", args.mesh, "--scale", str(args.scale), "--subdivide", str(subdivide),
               "--start", repr(x), "0.06", repr(z), "--direction", repr(dx), "0", repr(dz), "--length", repr(length),
               "--depth", repr(depth), "--out", out]
    run = subprocess.run(command, capture_output=True, text=True)
    summary = os.path.join(out, "summary.json")
    if run.returncode == 2 or not os.path.exists(summary):
        return None
    with open(summary) as f:
        s = json.load(f)
    figures = s["incision_figures"][0] if s["incision_figures"] else {}
    return {"exit": run.returncode, "pairs": s["mesh"]["self_intersections"],
            "shortfall": figures.get("shortfall"), "stroke_mm": round(1e3 * figures.get("stroke_length_m", 0.0), 2),
            "through": figures.get("through")}


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("mesh")
    p.add_argument("--incise", default="build/apps/incise")
    p.add_argument("--scale", type=float, default=0.1)
    p.add_argument("--strokes", type=int, default=60)
    p.add_argument("--seed", type=int, default=20261207)
    p.add_argument("--subdivide", type=int, nargs="+", default=[0, 2])
    p.add_argument("--out", default="/tmp/random_cuts")
    args = p.parse_args()
    if not os.path.exists(args.mesh):
        sys.exit(f"random_cuts.py: {args.mesh}: no such file")
    rng = random.Random(args.seed)
    in_contact = crossing = pairs = 0
    for index in range(args.strokes):
        stroke = draw(rng)
        for subdivide in args.subdivide:
            result = cut(args, index, subdivide, stroke)
            if result is None:
                print(f"{index} subdivide {subdivide}: no contact")
                continue
            in_contact += 1
            crossing += 1 if result["pairs"] > 0 else 0
            pairs += result["pairs"]
            print(f"{index} subdivide {subdivide}: " + json.dumps(result))
    print(f"cuts in contact {in_contact}, with crossing faces {crossing}, pairs {pairs}")


if __name__ == "__main__":
    main()

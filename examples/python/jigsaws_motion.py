#!/usr/bin/python3
"""Reads JIGSAWS kinematics files (the da Vinci's recorded arms, 76 columns at 30 Hz), scores each arm's
motion as `incise score` scores a session that never touches the tissue (path length, straight line,
economy, smoothness: SPARC and log dimensionless jerk), and plots the tip's speed over time with the
figures. Writes a PNG (matplotlib, no display needed).

    python3 jigsaws_motion.py FILE.txt [FILE.txt ...] [--arm psm-right] [--out jigsaws.png]
    python3 jigsaws_motion.py --demo            (a synthetic file: a tip circling twice, then a figure eight)
"""
import argparse
import math
import pathlib
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import incise  # noqa: E402


def write_demo(folder):
    """A JIGSAWS-format file (every arm the same): 3 s of circles, then 3 s of a figure eight, at 30 Hz."""
    path = pathlib.Path(folder) / "Demo_B001.txt"
    rows = []
    for k in range(180):
        a = 2 * math.pi * k / 90
        x, z = (0.02 * math.cos(a), 0.02 * math.sin(a)) if k < 90 else (0.02 * math.cos(a), 0.01 * math.sin(2 * a))
        arm = [x, 0.12, z, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0.3]
        rows.append("   " + "   ".join(f"{value:.6f}" for value in (arm * 4)))
    path.write_text("\n".join(rows) + "\n")
    return str(path)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="*")
    parser.add_argument("--arm", default="psm-right", help="mtm-left, mtm-right, psm-left or psm-right")
    parser.add_argument("--out", default="jigsaws.png")
    parser.add_argument("--demo", action="store_true", help="score a synthetic file")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        files = args.files + ([write_demo(folder)] if args.demo or not args.files else [])
        sessions = [incise.read_jigsaws(f, arm=args.arm) for f in files]  # N x 10 pose arrays
        # Any scenario without a plan scores the motion alone; the shipped bunny-straight will do.
        scores = incise.score(incise.shipped("bunny-straight.json"), sessions)
        fig, ax = plt.subplots(figsize=(8, 4))
        for name, poses, score in zip(files, sessions, scores):
            s = score["session"]
            t, tip = poses[:, 0], poses[:, 1:4]
            speed = np.linalg.norm(np.diff(tip, axis=0), axis=1) / np.diff(t)
            label = (f"{pathlib.Path(name).stem}: path {1e3 * s['path_length_m']:.0f} mm, "
                     f"economy {s['economy']:.2f}, SPARC {s['sparc']:.2f}")
            ax.plot(t[1:], 1e3 * speed, label=label)
            print(f"{pathlib.Path(name).name} ({args.arm}): {s['time_s']:.1f} s, path {1e3 * s['path_length_m']:.1f} mm, "
                  f"economy {s['economy']:.3f}, SPARC {s['sparc']:.3f}, LDLJ {s['log_dimensionless_jerk']:.2f}")
        ax.set_xlabel("time (s)")
        ax.set_ylabel("tip speed (mm/s)")
        ax.set_title(f"JIGSAWS {args.arm}: motion scored by incise")
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(args.out, dpi=120)
        print(f"wrote {args.out}")


if __name__ == "__main__":
    main()

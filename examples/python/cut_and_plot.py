#!/usr/bin/python3
"""Cuts the shipped Stanford bunny with one stroke, as `incise cut` does, and draws the cut from above: the
skin shaded grey, the wound's walls red. Writes a PNG (matplotlib, no display needed).

    python3 cut_and_plot.py [OUT.png]          (default: cut.png)
"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402

import incise  # noqa: E402


def main(out):
    cut = incise.cut(length=0.04, depth=0.004)  # the shipped bunny, a 4 cm stroke along +x
    s = cut.summary
    print(f"{s['mesh']['vertices']} vertices, {s['mesh']['faces']} faces ({s['mesh']['wall_faces']} wall); "
          f"groove {1e3 * s['incision_figures'][0]['groove_length_m']:.1f} mm; ok: {cut.ok}")

    v, f, wall = cut.vertices, cut.faces, cut.wall  # N x 3 (metres), M x 3, M bool
    corners = v[f]  # M x 3 x 3
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    # Seen from above (+y): the faces that face up, around the cut, drawn lowest first.
    centre = corners.mean(axis=1)
    near = (normals[:, 1] > 0) & (np.abs(centre[:, 2] - 0.015) < 0.012) & (centre[:, 0] > -0.02) & (centre[:, 0] < 0.04)
    order = np.argsort(centre[near, 1])
    shade = 0.35 + 0.6 * normals[near][order] @ np.array([0.3, 0.9, 0.3])
    colours = np.where(wall[near][order, None], [[0.85, 0.1, 0.1, 1.0]] * len(order),
                       np.column_stack([shade, shade, shade, np.ones(len(order))]))
    polygons = corners[near][order][:, :, [0, 2]] * 1e3  # x and z, millimetres

    fig, ax = plt.subplots(figsize=(8, 4))
    ax.add_collection(PolyCollection(polygons, facecolors=colours, edgecolors="none"))
    ax.autoscale()
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("z (mm)")
    ax.set_title("incise.cut: a 4 cm stroke across the bunny's back (walls red)")
    fig.tight_layout()
    fig.savefig(out, dpi=150)
    print(f"wrote {out}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "cut.png")

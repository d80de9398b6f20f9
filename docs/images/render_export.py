"""Render an exported STL to a small PNG (the README's picture of an exported pair).

    beveloid example case1 > pair.toml     # then add bore_diameter_mm = 60 to [pinion], 100 to [gear]
    beveloid export pair.toml --format stl --assembled --out out
    python docs/images/render_export.py out/pair_pair.stl docs/images/export_case1_pair.png
"""
from __future__ import annotations

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import trimesh  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402


def render(stl_path, png_path, elev=38.0, azim=-75.0):
    mesh = trimesh.load(stl_path, file_type="stl")
    parts = sorted(mesh.split(only_watertight=True), key=lambda m: m.volume)
    fig = plt.figure(figsize=(6.4, 4.2), dpi=100)
    ax = fig.add_subplot(projection="3d")
    light = np.array([0.4, -0.5, 0.75])
    light /= np.linalg.norm(light)
    for part, base in zip(parts, ([0.80, 0.45, 0.20], [0.35, 0.50, 0.75])):
        shade = 0.35 + 0.65 * np.clip(part.face_normals @ light, 0.0, 1.0)
        colors = np.clip(np.asarray(base)[None, :] * shade[:, None], 0, 1)
        ax.add_collection3d(Poly3DCollection(part.triangles, facecolors=colors, edgecolors="none", linewidths=0))
    lo, hi = mesh.bounds
    centre, half = (lo + hi) / 2, 0.32 * (hi - lo).max()
    for set_lim, c in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), centre):
        set_lim(c - half, c + half)
    ax.set_box_aspect((1, 1, 1))
    ax.view_init(elev=elev, azim=azim)
    ax.set_axis_off()
    fig.subplots_adjust(0, 0, 1, 1)
    fig.savefig(png_path, dpi=100, bbox_inches="tight", pad_inches=0.02)


if __name__ == "__main__":
    render(sys.argv[1], sys.argv[2])

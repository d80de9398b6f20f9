"""Figures of the tribology: the sliding velocity field and the flash temperature on the pinion flank
over the cycle, and the efficiency map (torque x speed)."""
from __future__ import annotations

import numpy as np

from ..plots import flank_outline


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _write(fig, out_png, title):
    if title:
        fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(out_png, dpi=110)
    _pyplot().close(fig)


def _flank_coordinates(tri, result):
    """(z, radius) on the pinion flank (member frame) of every loaded cell, and the mask."""
    pts = result.gap.pinion_point
    loaded = tri.cells.loaded
    p = pts[loaded]
    return p[:, 2], np.hypot(p[:, 0], p[:, 1]), loaded


def _sliding_in_flank(tri, result, geom):
    """The sliding velocity of the loaded cells (m/s) as (dz, dr) on the pinion flank (member frame)."""
    from ..generated import placement

    rot = placement.pinion_placement(result.pair_pinion_angle, geom.placement()).rotation  # (N, P, 3, 3)
    w = tri.speed_rpm * np.pi / 30
    v1 = np.einsum("npji,npcj->npci", rot, tri.cells.sliding_velocity) * w  # S_f -> S_1
    p = result.gap.pinion_point
    loaded = tri.cells.loaded
    v, q = v1[loaded], p[loaded]
    r = np.hypot(q[:, 0], q[:, 1])
    return v[:, 2], (q[:, 0] * v[:, 0] + q[:, 1] * v[:, 1]) / r


def flank_fields(tri, result, geom, out_png, title=""):
    """Two panels on the pinion flank over the whole cycle (every loaded cell of every position):
    the sliding speed with its direction (arrows: the pinion surface relative to the gear's), and
    Blok's flash temperature."""
    plt = _pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8))
    z, rad, _ = _flank_coordinates(tri, result)
    zb, rb = flank_outline(geom, "pinion", result.flank)
    loaded = tri.cells.loaded
    vs = tri.cell_sliding_m_s[loaded]
    flash = tri.cell_flash_c[loaded]
    for ax, values, label, cmap in ((axes[0], vs, "sliding speed (m/s)", "viridis"),
                                    (axes[1], flash, "flash temperature (K above the bulk)", "inferno")):
        ax.plot(zb, rb, color="0.3", lw=1.0)
        if values.size:
            sc = ax.scatter(z, rad, c=values, s=6, cmap=cmap, linewidths=0)
            fig.colorbar(sc, ax=ax).set_label(label, fontsize=8)
        ax.set_xlabel("axial position z (mm), toe -> heel", fontsize=8)
        ax.set_ylabel("radius (mm)", fontsize=8)
    if vs.size:
        dz, dr = _sliding_in_flank(tri, result, geom)
        step = max(1, vs.size // 250)  # about 250 arrows
        axes[0].quiver(z[::step], rad[::step], dz[::step], dr[::step], color="white", width=0.003,
                       edgecolor="k", linewidth=0.3)
    axes[0].set_title("pinion flank: sliding velocity over the cycle", fontsize=9)
    where = tri.flash_temperature_at
    axes[1].set_title(f"pinion flank: flash temperature, max {tri.flash_temperature_max_c:.1f} K"
                      if where is not None else "pinion flank: flash temperature", fontsize=9)
    if where is not None:
        p = result.gap.pinion_point[where.position, where.pair, where.cell]
        axes[1].plot([p[2]], [np.hypot(p[0], p[1])], "c*", ms=12, label="maximum")
        axes[1].legend(fontsize=7)
    _write(fig, out_png, title)


def efficiency_map(grid, out_png, title=""):
    """Efficiency (and mesh power loss) against the torque, one line per speed; ``grid`` the
    [[TribologyResult per speed] per torque] of :func:`beveloid.tribology.efficiency_map`."""
    plt = _pyplot()
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.2))
    torques = [row[0].torque_nm for row in grid]
    for s in range(len(grid[0])):
        label = f"{grid[0][s].speed_rpm:g} rpm"
        a1.plot(torques, [row[s].efficiency * 100 for row in grid], "o-", label=label)
        a2.plot(torques, [row[s].mesh_power_loss_w for row in grid], "o-", label=label)
    a1.set_ylabel("mesh efficiency (%)")
    a2.set_ylabel("mesh power loss (W)")
    for ax in (a1, a2):
        ax.set_xlabel("pinion torque (N m)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    _write(fig, out_png, title)

"""Figures of the LTCA: the loaded contact pattern (the max pressure over the cycle on each flank,
like a measured pattern), the loaded TE and load sharing, and the pressure map of every position."""
from __future__ import annotations

import numpy as np

from ...plots import PINION_ANGLE_LABEL, pinion_angle_deg, pinion_angle_text

PRESSURE_LABEL = "max pressure over the cycle (MPa)"


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _save(fig, out_png, title=""):
    plt = _plt()
    if title:
        fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(out_png, dpi=110)
    plt.close(fig)


def surface_scale_mpa(result):
    """The colour scale's top: the largest surface-contact peak over the converged positions.

    The edge peaks at a blank's edge are singular and grow with the grid (docs/validation.md 7.2);
    scaled to them, a pattern shows one dark cell and the rest pale. None when no cell is clear of
    the edges (then the scale runs to the largest pressure)."""
    surf = result.pair_surface_max_pressure_mpa[result.converged]
    return float(np.nanmax(surf)) if np.isfinite(surf).any() else None


def _colorbar(fig, sc, ax, label, clipped, fontsize=8, **kw):
    """A colour bar whose arrow says that pressures above the scale (edge peaks) are drawn at its top."""
    cb = fig.colorbar(sc, ax=ax, extend="max" if clipped else "neither", **kw)
    cb.set_label(label + ("; edge peaks above the scale" if clipped else ""), fontsize=fontsize)
    return cb


def _cell_corners(centres: np.ndarray) -> np.ndarray:
    """(n, m) cell centres -> (n + 1, m + 1) cell corners: the mean of the four neighbouring centres,
    the raster extended by one linearly extrapolated row and column on each side.  Matplotlib's own
    "nearest" shading does the same but warns where the raster folds in (z, radius) (its coordinates
    are then not monotonic), which some flanks do near the root."""
    n, m = centres.shape
    e = np.empty((n + 2, m + 2))
    e[1:-1, 1:-1] = centres
    e[0, 1:-1] = 2 * centres[0] - centres[1] if n > 1 else centres[0]
    e[-1, 1:-1] = 2 * centres[-1] - centres[-2] if n > 1 else centres[-1]
    e[:, 0] = 2 * e[:, 1] - e[:, 2] if m > 1 else e[:, 1]
    e[:, -1] = 2 * e[:, -2] - e[:, -3] if m > 1 else e[:, -2]
    return 0.25 * (e[:-1, :-1] + e[1:, :-1] + e[:-1, 1:] + e[1:, 1:])


def ltca_pattern(ax, result, geom, member, vmax=None):
    """The max pressure over the cycle on one member's flank raster, in (axial position z, radius).

    The colour runs to ``vmax`` (default: the surface-contact peak over the cycle, surface_scale_mpa);
    returns the artist and whether any pressure lies above the scale, or (None, False)."""
    from ...plots import flank_outline

    pat = result.pattern(member)
    zb, rb = flank_outline(geom, member, result.flank)
    ax.plot(zb, rb, color="0.3", lw=1.0)
    ax.set_xlabel("axial position z (mm), toe -> heel", fontsize=8)
    ax.set_ylabel("radius (mm)", fontsize=8)
    if not pat.points.size:
        return None, False
    vmax = surface_scale_mpa(result) if vmax is None else vmax
    pts = pat.raster_points
    z, rad = pts[..., 2], np.hypot(pts[..., 0], pts[..., 1])
    shown = np.ma.masked_where(~pat.raster_inside, pat.raster_pressure_mpa)
    loaded = np.ma.masked_where(~pat.raster_inside | (pat.raster_pressure_mpa <= 0), shown)
    zc, rc = _cell_corners(z), _cell_corners(rad)  # the raster's cells; its nodes are their centres
    ax.pcolormesh(zc, rc, np.ma.masked_where(~pat.raster_inside, np.zeros(z.shape)), cmap="Greys", vmin=-1,
                  vmax=12, shading="flat")  # the flank, light grey
    sc = ax.pcolormesh(zc, rc, loaded, cmap="inferno_r", vmin=0, vmax=vmax, shading="flat")
    frac = "-" if pat.area_fraction is None else f"{pat.area_fraction * 100:.0f}%"
    ax.set_title(f"{member}: {frac} of the flank loaded", fontsize=9)
    clipped = vmax is not None and bool(np.ma.max(loaded) > vmax) if loaded.count() else False
    return sc, clipped


def root_stress_panel(ax, result):
    """The FE tooth's root stress along the face (max principal in the loaded fillet) of each
    member's most loaded tooth: the (position, pair) of its largest root stress."""
    where = result.root_stress_location()
    for member, (z, s) in result.root_stress_along_face.items():
        w = where.get(member)
        label = member if w is None else f"{member}, position {w['position']}, pair {w['pair']}"
        ax.plot(z, s, "o-", ms=3, label=label)
    ax.set_xlabel("z along the face (mm, member frame)")
    ax.set_ylabel("root stress, max principal (MPa)")
    ax.set_title("root stress along the face (FE tooth)", fontsize=9)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)


def ltca_summary(result, geom, out_png, title=""):
    """Contact patterns of both members, loaded TE and load sharing; the per-position pressure maps
    go to ``<out>_positions.png`` beside it."""
    plt = _plt()
    fe = bool(result.root_stress_along_face)
    fig, axes = plt.subplots(2, 3 if fe else 2, figsize=(16 if fe else 11, 7.5))
    if fe:
        root_stress_panel(axes[0, 2], result)
        axes[1, 2].axis("off")
    for ax, member in ((axes[0, 0], "pinion"), (axes[0, 1], "gear")):
        sc, clipped = ltca_pattern(ax, result, geom, member)
        if sc is not None:
            _colorbar(fig, sc, ax, PRESSURE_LABEL, clipped)
    phi = pinion_angle_deg(result.pinion_angle)
    ax = axes[1, 0]
    ax.plot(phi, result.unloaded_te * 1e6, "--", color="0.5", label="unloaded (rigid) TE")
    ax.plot(phi, result.loaded_te * 1e6, "o-", ms=3, label=f"loaded TE, {result.torque_nm:g} N m")
    ax.set_xlabel(PINION_ANGLE_LABEL)
    ax.set_ylabel("TE (urad)")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    ax = axes[1, 1]
    for k, pair in enumerate(result.tooth_pairs):
        ax.plot(phi, result.pair_load_n[:, k], "o-", ms=3, label=f"tooth pair {pair}")
    ax.set_xlabel(PINION_ANGLE_LABEL)
    ax.set_ylabel("normal load (N)")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    _save(fig, out_png, title)
    out = str(out_png)
    position_maps(result, geom, (out[:-4] if out.endswith(".png") else out) + "_positions.png", title)


def position_maps(result, geom, out_png, title="", member="pinion"):
    """The pressure of every pair at each position on one member's flank (one panel a position)."""
    from ...plots import flank_outline

    plt = _plt()
    N = len(result.status)
    cols = min(N, 5)
    rows = -(-N // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(2.7 * cols + 1.0, 2.6 * rows + 0.6), squeeze=False,
                             layout="constrained")
    zb, rb = flank_outline(geom, member, result.flank)
    pts = result.gap.pinion_point if member == "pinion" else result.gap.gear_point
    top = float(np.nanmax(np.where(result.converged[:, None, None], result.pressure_mpa, 0.0)))
    vmax = surface_scale_mpa(result) or top or 1.0
    clipped = top > vmax
    sc = None
    for j, ax in enumerate(axes.ravel()):
        if j >= N:
            ax.axis("off")
            continue
        ax.plot(zb, rb, color="0.3", lw=0.8)
        p = result.pressure_mpa[j]
        on = (p > 0) & result.converged[j]
        q = pts[j][on]
        sc = ax.scatter(q[:, 2], np.hypot(q[:, 0], q[:, 1]), s=3, c=p[on], cmap="inferno_r", vmin=0, vmax=vmax, lw=0)
        ax.set_title(f"{pinion_angle_text(result.pinion_angle[j], words=False)}: {result.status[j]}", fontsize=8)
        ax.tick_params(labelsize=6)
        if j % cols == 0:
            ax.set_ylabel("radius (mm)", fontsize=7)
        if j // cols == rows - 1:
            ax.set_xlabel("axial position z (mm)", fontsize=7)
    if sc is not None:
        _colorbar(fig, sc, axes.ravel().tolist(), "pressure (MPa)", clipped, shrink=0.8, aspect=30)
    if title:
        fig.suptitle(f"{title}: {member} pressure at each position", fontsize=9)
    fig.savefig(out_png, dpi=100)
    plt.close(fig)


def ltca_torques(results, geom, out_png, title=""):
    """Figs 24-25 style: patterns on both flanks at each torque (columns), loaded TE and load sharing."""
    plt = _plt()
    n = len(results)
    fig, axes = plt.subplots(4, n, figsize=(3.4 * n, 12), squeeze=False)
    for c, res in enumerate(results):
        for r, member in enumerate(("pinion", "gear")):
            ax = axes[r, c]
            sc, clipped = ltca_pattern(ax, res, geom, member)
            ax.set_title(f"T1 = {res.torque_nm:g} N m, " + ax.get_title(), fontsize=8)
            ax.tick_params(labelsize=7)
            if sc is not None:
                cb = _colorbar(fig, sc, ax, PRESSURE_LABEL, clipped, fraction=0.05, fontsize=6)
                cb.ax.tick_params(labelsize=6)
        phi = pinion_angle_deg(res.pinion_angle)
        ax = axes[2, c]
        ax.plot(phi, res.unloaded_te * 1e6, "--", color="0.5", lw=1)
        ax.plot(phi, res.loaded_te * 1e6, "o-", ms=2)
        ax.set_title("loaded TE", fontsize=8)
        ax.set_ylabel("TE (urad)", fontsize=7)
        ax.tick_params(labelsize=7)
        ax.grid(alpha=0.3)
        ax = axes[3, c]
        for k, pair in enumerate(res.tooth_pairs):
            ax.plot(phi, res.pair_load_n[:, k], "o-", ms=2, label=f"pair {pair}")
        ax.set_title("pair normal load", fontsize=8)
        ax.set_ylabel("normal load (N)", fontsize=7)
        ax.set_xlabel(PINION_ANGLE_LABEL, fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(alpha=0.3)
    axes[3, 0].legend(fontsize=7)
    _save(fig, out_png, title)


def te_map(results, out_png, title=""):
    """The loaded TE peak-to-peak against torque (the standard chart) and each torque's TE spectrum (mesh
    orders 1-6, :func:`beveloid.ltca.results.batch.te_harmonics`)."""
    from .batch import MESH_ORDERS, te_harmonics

    plt = _plt()
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.2))
    torque = [r.torque_nm for r in results]
    a.plot(torque, [r.loaded_te_peak_to_peak * 1e6 for r in results], "o-")
    a.set_xlabel("pinion torque (N m)")
    a.set_ylabel("loaded TE peak-to-peak (urad)")
    a.grid(alpha=0.3)
    width = 0.8 / len(results)
    for i, r in enumerate(results):
        b.bar(np.array(MESH_ORDERS) + (i - (len(results) - 1) / 2) * width, te_harmonics(r) * 1e6, width,
              label=f"{r.torque_nm:g} N m")
    b.set_xlabel("mesh order")
    b.set_ylabel("TE amplitude (urad)")
    b.set_xticks(MESH_ORDERS)
    b.legend(fontsize=8)
    b.grid(alpha=0.3, axis="y")
    _save(fig, out_png, title)


def tolerance_box(results, box, out_png, title=""):
    """The tolerance box of ``beveloid ltca --samples``: each error set's loaded TE peak-to-peak against its
    largest peak pressure (edges included), per torque, the file's errors starred; ``results`` the runs at
    the file's errors (one per torque), ``box`` [[batch.summary per torque] per error set]."""
    from .batch import summary

    plt = _plt()
    fig, ax = plt.subplots(figsize=(6.5, 4.8))
    for t, r in enumerate(results):
        te = [row[t]["te_peak_to_peak_urad"] for row in box]
        p = [row[t]["max_pressure_mpa"] for row in box]
        dots = ax.plot(te, p, "o", ms=4, alpha=0.7, label=f"{r.torque_nm:g} N m: {len(box)} error sets")[0]
        own = summary(r)
        ax.plot([own["te_peak_to_peak_urad"]], [own["max_pressure_mpa"]], "*", ms=13, color=dots.get_color(),
                mec="k", label=f"{r.torque_nm:g} N m: the file's errors")
    ax.set_xlabel("loaded TE peak-to-peak (urad)")
    ax.set_ylabel("largest peak pressure, edges included (MPa)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    _save(fig, out_png, title)

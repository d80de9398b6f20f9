"""The micro-geometry study of ``beveloid paper`` (issue 20): what tip relief and end relief do
to the paper's two cases, measured.

Both members of each case get the "micro_geometry" tooth-surface model
(derivations/flank_micro_geometry.py) with the same modification:

* **tip relief** (TIP_RELIEF): the loaded contact of Figs 24-25 at 200-600 N m with and without
  it: the maximum contact pressure and the loaded TE (mean and peak-to-peak over one mesh cycle);
* **end relief** (END_RELIEF): the unloaded TCA under the paper's largest assembly errors
  (dq = dx = dy = dz = +-1 mm, the largest dgamma_h and dgamma_v of Figs 10-21): the share of the
  mesh cycle carried by an edge contact on the toe or the heel, the TE peak-to-peak, and the
  loaded maximum pressure at LOADED_TORQUE_NM under the same errors;
* the LTCA peak pressure against the grid, with and without the tip relief (does it converge?);
* plots: the modification map (delta over z and radius), TE and maximum pressure against torque.

Fast settings (part of ``beveloid paper``): POSITIONS positions per mesh cycle, a GRID LTCA grid.
"""
from __future__ import annotations

import dataclasses
import math
import time
import warnings

import numpy as np

from ..mesh import cycle_positions_text

DEG = math.pi / 180
CASES = ("case1", "case2")
FLANK = "right"
TORQUES_NM = (200.0, 400.0, 600.0)
POSITIONS = 5
GRID = (11, 21)
GRIDS = ((11, 21), (15, 31), (21, 45))  # the convergence table
LOADED_TORQUE_NM = 400.0
#: tip relief: amount (um) and height (in normal modules); parabolic
TIP_RELIEF = dict(tip_relief_um=30.0, tip_relief_height_mm=0.4, tip_relief_shape="parabolic")
#: end relief: amount (um) and length (share of the face width); parabolic
END_RELIEF = dict(end_relief_um=40.0, end_relief_length_mm=0.2, end_relief_shape="parabolic")
#: the largest errors of Figs 10-21, per case: (label, (dx, dy, dz mm, vertical, horizontal deg))
ERRORS = {
    "case1": (("dq = +1 mm", (1.0, 1.0, 1.0, 0, 0)), ("dq = -1 mm", (-1.0, -1.0, -1.0, 0, 0)),
              ("dgh = +0.03 deg", (0, 0, 0, 0, 0.03)), ("dgh = -0.03 deg", (0, 0, 0, 0, -0.03)),
              ("dgv = +0.2 deg", (0, 0, 0, 0.2, 0)), ("dgv = -0.2 deg", (0, 0, 0, -0.2, 0))),
    "case2": (("dq = +1 mm", (1.0, 1.0, 1.0, 0, 0)), ("dq = -1 mm", (-1.0, -1.0, -1.0, 0, 0)),
              ("dgh = +0.04 deg", (0, 0, 0, 0, 0.04)), ("dgh = -0.04 deg", (0, 0, 0, 0, -0.04)),
              ("dgv = +0.25 deg", (0, 0, 0, 0.25, 0)), ("dgv = -0.25 deg", (0, 0, 0, -0.25, 0))),
}
_OFF = dict(profile_crowning_um=0.0, lead_crowning_um=0.0, tip_relief_um=0.0, tip_relief_height_mm=1.0,
            tip_relief_shape="parabolic", end_relief_um=0.0, end_relief_length_mm=1.0, end_relief_shape="parabolic",
            lead_slope_um=0.0)


def modification(geom, tip=True, ends=True) -> dict:
    """The study's surface options for a pair (heights and lengths scaled to its module and faces)."""
    out = dict(_OFF)
    if tip:
        out.update(TIP_RELIEF, tip_relief_height_mm=TIP_RELIEF["tip_relief_height_mm"] * geom.normal_module_mm)
    if ends:
        out.update(END_RELIEF)
    return out


def modified(geom, tip=True, ends=True):
    """The pair with both members on the micro-geometry model (end lengths per member's face)."""
    def member(m):
        o = modification(geom, tip, ends)
        if ends:
            o["end_relief_length_mm"] = END_RELIEF["end_relief_length_mm"] * m.face_width_mm
        return dataclasses.replace(m, tooth_surface="micro_geometry", surface_options=tuple(sorted(o.items())))
    return dataclasses.replace(geom, pinion=member(geom.pinion), gear=member(geom.gear))


def _err(e):
    return (e[0], e[1], e[2], e[3] * DEG, e[4] * DEG)


def loaded_rows(geom, label, torques=TORQUES_NM, errors=(0, 0, 0, 0, 0), grid=GRID):
    """[(label, torque, max pressure MPa, loaded TE mean urad, p-p urad, converged)] over torques."""
    from .. import ltca

    rows = []
    for t in torques:
        r = ltca.analyze(geom, ltca.LoadCase(t, errors=tuple(errors)), ltca.Options(flank=FLANK, positions=POSITIONS, grid=tuple(grid), tooth_model="plate"))
        ok = r.converged
        te = r.loaded_te[ok] * 1e6
        rows.append((label, t, float(np.nanmax(r.pair_max_pressure_mpa)) if ok.any() else math.nan,
                     float(te.mean()) if ok.any() else math.nan, float(np.ptp(te)) if ok.any() else math.nan,
                     int(ok.sum())))
    return rows


def edge_share(geom, errors):
    """(share of the active contact that is an edge contact on a toe or a heel, TE p-p urad)."""
    from .. import tca

    fr = tca.mesh_flank(geom, FLANK, errors, positions=60)
    act = np.asarray(fr.active, dtype=bool)
    names = fr.contact_boundary if fr.contact_boundary is not None else [None] * len(act)
    ends = np.array([n is not None and ("toe" in n or "heel" in n) for n in names])
    n_act = max(int(act.sum()), 1)
    return float((act & ends).sum()) / n_act, float(fr.te_peak_to_peak) * 1e6


def delta_map(geom, member="pinion", n=161):
    """(z from the face centre mm, radius mm, delta um) over the member's active flank: the
    distance between the base (crowned) point and the modified one, from the kernels.

    The (l, u) raster reaches past the face (|u| <= 0.65 W): a helical flank's generating lines
    cross the toe and heel planes obliquely, so |u| <= W/2 would leave corners of the blank out;
    points outside the blank are nan."""
    from ..generated import tca_kernels

    m = geom.member(member)
    base = dataclasses.replace(m, tooth_surface="crowned", surface_options=tuple(
        (k, v) for k, v in m.surface_options if k in ("profile_crowning_um", "lead_crowning_um")))
    g_base = dataclasses.replace(geom, **{member: base})
    lmax = (m.tip_height_mm + m.cutter_addendum_mm) / math.cos(geom.normal_pressure_angle)
    l, u = np.meshgrid(np.linspace(0.0, lmax, n), np.linspace(-0.65, 0.65, n) * m.face_width_mm, indexing="ij")
    q, nrm, _ = tca_kernels.surface("crowned", FLANK, l, u, g_base.surface_params(member))
    p = tca_kernels.surface("micro_geometry", FLANK, l, u, geom.surface_params(member)).point
    rho = np.hypot(q[..., 0], q[..., 1])
    z = q[..., 2] - m.reference_section_offset_mm
    inside = (rho <= m.tip_radius(q[..., 2])) & (np.abs(z) <= m.face_width_mm / 2)  # the blank
    delta = np.where(inside, np.einsum("...i,...i", q - p, nrm) * 1e3, np.nan)
    return z, rho, delta


def _plots(out, maps, loaded):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import MaxNLocator

    fig, axes = plt.subplots(1, len(maps), figsize=(5.5 * len(maps), 4.2), squeeze=False)
    for ax, (case, (z, rho, d)) in zip(axes[0], maps.items()):
        top = float(np.nanmax(d))
        levels = MaxNLocator(12).tick_values(0.0, top) if top > 0 else np.array([-0.5, 0.5])
        d = np.where(np.abs(d) < 1e-6, 0.0, d)  # the unmodified zone's round-off (~1e-9 um, either sign)
        pc = ax.contourf(z, rho, np.ma.masked_invalid(d), levels=levels, cmap="viridis")
        if top > 0.1:  # where the relief starts (its kink lines)
            ax.contour(z, rho, np.ma.masked_invalid(d), levels=[0.1], colors="w", linewidths=0.8)
        fig.colorbar(pc, ax=ax, label="removal delta (um); white line: 0.1 um")
        ax.set_xlabel("z from the face centre (mm)")
        ax.set_ylabel("radius (mm)")
        ax.set_title(f"{case}: pinion modification map ({FLANK} flank)")
    fig.tight_layout()
    fig.savefig(out / "micro_geometry_map.png", dpi=110)
    plt.close(fig)
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.2))
    for (case, label), rows in loaded.items():
        t = [r[1] for r in rows]
        style = "-" if label == "tip relief" else "--"
        a1.plot(t, [r[3] for r in rows], style, marker="o", label=f"{case}, {label}")
        a2.plot(t, [r[2] for r in rows], style, marker="o", label=f"{case}, {label}")
    a1.set_xlabel("pinion torque (N m)")
    a1.set_ylabel("loaded TE, mean over the cycle (urad)")
    a2.set_xlabel("pinion torque (N m)")
    a2.set_ylabel("maximum contact pressure (MPa)")
    a1.legend(fontsize=8)
    a2.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "micro_geometry_torque.png", dpi=110)
    plt.close(fig)


def _csv(path, header, rows):
    with open(path, "w") as f:
        f.write(",".join(header) + "\n")
        for r in rows:
            f.write(",".join(str(v) for v in r) + "\n")


def case_task(case):
    """:func:`case_data` of a paper case (``beveloid paper`` runs each on a worker process)."""
    from ..pair import Pair
    from .tasks import say

    return case_data(Pair.example(case).geometry, case, say)


def case_data(g, case, progress=lambda msg: None, grids=GRIDS):
    """One case of the study: ({(case, flanks): loaded rows}, modification map, error rows, grid rows, seconds)."""
    t0 = time.perf_counter()
    loaded, edge_rows, grid_rows = {}, [], []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # diverging Newton iterates overflow in numpy
        tip = modified(g, ends=False)
        progress(f"   micro-geometry {case}: tip relief under load")
        loaded[case, "unmodified"] = loaded_rows(g, "unmodified")
        loaded[case, "tip relief"] = loaded_rows(tip, "tip relief")
        both = modified(g)
        delta = delta_map(both)
        progress(f"   micro-geometry {case}: end relief under the largest errors")
        for label, e in ERRORS[case]:
            row = [case, label]
            for name, geom in (("unmodified", g), ("end + tip relief", both)):
                share, te = edge_share(geom, _err(e))
                pmax = loaded_rows(geom, name, (LOADED_TORQUE_NM,), _err(e))[0][2]
                row += [share, te, pmax]
            edge_rows.append(tuple(row))
        for grid in grids:
            for name, geom in (("unmodified", g), ("tip relief", tip)):
                grid_rows.append((case, name, f"{grid[0]}x{grid[1]}",
                                  loaded_rows(geom, name, (600.0,), grid=grid)[0][2]))
    return loaded, delta, edge_rows, grid_rows, time.perf_counter() - t0


def finish(out, parts):
    """Plots, CSV and the report's lines from :func:`case_data`'s results ({case: result}, in order)."""
    loaded, maps, edge_rows, grid_rows, seconds = {}, {}, [], [], 0.0
    for case, (case_loaded, delta, case_edges, case_grids, s) in parts.items():
        loaded.update(case_loaded)
        maps[case] = delta
        edge_rows += case_edges
        grid_rows += case_grids
        seconds += s
    _plots(out, maps, loaded)
    _csv(out / "micro_geometry_loaded.csv", ["case", "flanks", "pinion_torque_nm", "max_pressure_mpa",
                                              "loaded_te_mean_urad", "loaded_te_ptp_urad", "converged_positions"],
         [(c, *r) for (c, _), rows in loaded.items() for r in rows])
    _csv(out / "micro_geometry_errors.csv", ["case", "errors", "toe_heel_edge_share_unmodified", "te_ptp_urad_unmodified",
                                              "max_pressure_mpa_unmodified", "toe_heel_edge_share_modified",
                                              "te_ptp_urad_modified", "max_pressure_mpa_modified"], edge_rows)
    return _report(loaded, edge_rows, grid_rows, seconds)


def _report(loaded, edge_rows, grid_rows, seconds):
    tip = TIP_RELIEF
    L = ["## Micro-geometry study (issue 20)", "",
         f"Both members: tip relief {tip['tip_relief_um']:g} um over {tip['tip_relief_height_mm']:g} m_n "
         f"({tip['tip_relief_shape']}); end relief {END_RELIEF['end_relief_um']:g} um over "
         f"{END_RELIEF['end_relief_length_mm']:g} of the face width ({END_RELIEF['end_relief_shape']}). "
         f"LTCA: {FLANK} flank, {cycle_positions_text(POSITIONS)}, the plate tooth, {GRID[0]} x {GRID[1]} cells.",
         "",
         "| case | flanks | T1 (N m) | max pressure (MPa) | loaded TE mean (urad) | loaded TE p-p (urad) | converged |",
         "|---|---|---|---|---|---|---|"]
    for (case, _), rows in loaded.items():
        for r in rows:
            L.append(f"| {case} | {r[0]} | {r[1]:g} | {r[2]:.0f} | {r[3]:.1f} | {r[4]:.1f} | {r[5]}/{POSITIONS} |")
    L += ["", f"Largest assembly errors, unloaded TCA (60 positions) and LTCA at {LOADED_TORQUE_NM:g} N m: share of "
          "the mesh cycle carried by a toe or heel edge contact, TE p-p, max pressure; unmodified -> end + tip relief.",
          "", "| case | errors | toe/heel edge share | TE p-p (urad) | max pressure (MPa) |", "|---|---|---|---|---|"]
    for r in edge_rows:
        L.append(f"| {r[0]} | {r[1]} | {r[2]:.0%} -> {r[5]:.0%} | {r[3]:.1f} -> {r[6]:.1f} | {r[4]:.0f} -> {r[7]:.0f} |")
    L += ["", "LTCA peak pressure at 600 N m against the grid (cells across x along):", "",
          "| case | flanks | grid | max pressure (MPa) |", "|---|---|---|---|"]
    L += [f"| {c} | {n} | {g} | {p:.0f} |" for c, n, g, p in grid_rows]
    L += ["", "![modification map](micro_geometry_map.png)", "", "![TE and pressure against torque]"
          "(micro_geometry_torque.png)", "", f"Computed in {seconds:.1f} s (data: micro_geometry_loaded.csv, "
          "micro_geometry_errors.csv; seconds of the processes' time).", ""]
    return L

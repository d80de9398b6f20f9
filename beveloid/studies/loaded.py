"""Figs 24-25 of the paper (loaded contact patterns at 5, 200, 400 and 600 N m) by the
approximate LTCA of :mod:`beveloid.ltca`, for ``beveloid paper``.

The captions of Figs 24-25 mix the members ("T = 5 Nm", "Gear T = 200 Nm", "Pinion T = 400 Nm",
"Gear T = 600 Nm").  Here every torque is the **pinion** torque T1 (the one the LTCA balances);
the gear torque of the same mesh is T2 = T1 N2/N1 (frictionless, the nominal ratio) and is
listed beside it.  The paper's patterns come from a commercial hybrid FE program; ours from a
half-space + thin-slice model, so they are compared in trend (pattern area against torque and
against the FPD angle), not pointwise.

Fast settings (the study is part of ``beveloid paper``): 8 positions over one mesh cycle, the
LTCA's default grid (the same rule as ``beveloid ltca``).
"""
from __future__ import annotations

import math
import time

import numpy as np

TORQUES_NM = (5.0, 200.0, 400.0, 600.0)  #: pinion torques
POSITIONS = 8
FIGURES = {"case1": "24", "case2": "25"}
FLANK = "right"


def run_loaded(out, geoms, designs, progress=lambda msg: None, tooth_model=None):
    """Compute the loaded study for both cases; write the figures and CSV into ``out``; return report lines.
    ``tooth_model``: "fe", "plate" or None (the LTCA's default: the FE tooth when gmsh and scikit-fem import)."""
    from .. import ltca
    from ..ltca import plots

    model = ltca.Options(torque_nm=1.0, tooth_model=tooth_model).tooth_model
    teeth = ("the FE tooth (beveloid/fe: gmsh mesh of each member's sector from the generated geometry, refinement"
             " 1; bending compliance and root stress; docs/loaded_contact.md)" if model == "fe" else
             "the plate tooth (thin slices of the equivalent spur tooth with the plate's face coupling)")

    t0 = time.perf_counter()
    rows = []
    lines = ["## Loaded contact (Figs 24-25), approximate LTCA", "",
             "Pinion torques T1 (the captions of Figs 24-25 mix pinion and gear torque; here all are pinion "
             "torques, the gear torque is T2 = T1 N2/N1). Right flank, one mesh cycle of "
             f"{POSITIONS} positions, the default grid (cells sized from each pair's Hertz semi-axes), steel. "
             "Pattern area: the share of the flank (between form limit, tip, toe and heel) that carries "
             "pressure somewhere in the cycle. Model and limits: docs/loaded_contact.md; checks: "
             "docs/validation.md.", "", f"Tooth model: **{model}**, {teeth}.", "",
             "| case | xi_R (deg) | T1 (N m) | T2 (N m) | pinion area | gear area | surface max pressure (MPa) | "
             "loaded TE mean (urad) | loaded TE p-p (urad) | max pair load share | converged | "
             "root stress pinion / gear (MPa) |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    figures = []
    for case, fig in FIGURES.items():
        g = geoms[case]
        results = []
        for t in TORQUES_NM:
            progress(f"   loaded contact {case}, T1 = {t:g} N m")
            r = ltca.analyze(g, ltca.Options(torque_nm=t, flank=FLANK, positions=POSITIONS, tooth_model=model))
            results.append(r)
            ok = r.converged
            fr = {m: r.pattern(g, m).area_fraction for m in ("pinion", "gear")}
            te = r.loaded_te[ok] * 1e6
            share = np.nanmax(r.pair_load_n[ok] / r.pair_load_n[ok].sum(axis=1, keepdims=True)) if ok.any() else np.nan
            row = (case, math.degrees(designs[case].fpd_angle_right), t, t * g.gear.teeth / g.pinion.teeth,
                   fr["pinion"], fr["gear"], float(np.nanmax(r.pair_surface_max_pressure_mpa)), float(te.mean()),
                   float(te.max() - te.min()), float(share), int(ok.sum()))
            rows.append(row)
            root = r.root_stress_max_mpa()
            root_text = " / ".join("-" if root.get(m) is None else f"{root[m]:.0f}" for m in ("pinion", "gear"))
            lines.append(f"| {case} | {row[1]:.2f} | {t:g} | {row[3]:.0f} | {_pct(row[4])} | {_pct(row[5])} | "
                         f"{row[6]:.0f} | {row[7]:.2f} | {row[8]:.2f} | {row[9]:.2f} | {row[10]}/{POSITIONS} | "
                         f"{root_text} |")
        plots.ltca_torques(results, g, out / f"fig{fig}_loaded_contact.png",
                           f"Fig {fig} - {case}: loaded contact at pinion torques "
                           f"{', '.join(f'{t:g}' for t in TORQUES_NM)} N m ({FLANK} flank, approximate LTCA, "
                           f"{model} tooth)")
        plots.position_maps(results[1], g, out / f"fig{fig}_loaded_positions.png",
                            f"Fig {fig} - {case}, T1 = {results[1].torque_nm:g} N m")
        figures.append(f"![Fig {fig}](fig{fig}_loaded_contact.png)")
        figures.append(f"![Fig {fig}, pressure at each position](fig{fig}_loaded_positions.png)")
    with open(out / "fig24_fig25_loaded.csv", "w") as f:
        f.write("case,fpd_angle_right_deg,pinion_torque_nm,gear_torque_nm,pinion_area_fraction,gear_area_fraction,"
                "surface_max_pressure_mpa,loaded_te_mean_urad,loaded_te_ptp_urad,max_pair_load_share,converged_positions\n")
        for r in rows:
            f.write(",".join(str(v) for v in r) + "\n")
    lines += [""] + [x for f in figures for x in (f, "")]
    lines += [f"Computed in {time.perf_counter() - t0:.1f} s (data: fig24_fig25_loaded.csv).", ""]
    return lines


def _pct(v):
    return "-" if v is None else f"{v * 100:.0f}%"

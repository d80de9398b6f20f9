"""Figs 24-25 of the paper (loaded contact patterns at 5, 200, 400 and 600 N m) by the
approximate LTCA of :mod:`beveloid.ltca`, for ``beveloid paper``.

The captions of Figs 24-25 mix the members ("T = 5 Nm", "Gear T = 200 Nm", "Pinion T = 400 Nm",
"Gear T = 600 Nm").  Here every torque is the **pinion** torque T1 (the one the LTCA balances);
the gear torque of the same mesh is T2 = T1 N2/N1 (frictionless, the nominal ratio) and is
listed beside it.  The paper's patterns come from a commercial hybrid FE program; ours from a
half-space + thin-slice model, so they are compared in trend (pattern area against torque and
against the FPD angle), not pointwise.

Fast settings (the study is part of ``beveloid paper``): 8 positions over one mesh cycle (the last one
pitch after the first: 7 distinct mesh states), the LTCA's default grid (the same rule as ``beveloid ltca``).
Each case is a piece of its own (:func:`case_task`, run on a worker process by ``paper``), and so is
each member's FE data the first time (:func:`submit_fe_teeth`).
"""
from __future__ import annotations

import math
import time

import numpy as np

from ..mesh import cycle_positions_text

TORQUES_NM = (5.0, 200.0, 400.0, 600.0)  #: pinion torques
POSITIONS = 8
FIGURES = {"case1": "24", "case2": "25"}
FLANK = "right"


#: the FE data of one member the first time, seconds of CPU on one thread (as on paper's workers), rounded
#: up: 11.3 s for the case 1 pinion and 12.0 s for its gear at refinement 1, 182 load cases each
#: (`MKL_NUM_THREADS=1 python -m benchmarks.bench_fe_tooth cost [--member gear]`, 2026-11-27, load average 1.0)
FE_FIRST_TIME_S = 12


def _say(text):
    from .tasks import say

    say(f"   {text}")


def _fe_source(case):
    """(the geometry and material the loaded study gives the LTCA, the LTCA's options for its FE tooth)."""
    from .. import ltca
    from ..pair import Pair

    return Pair.example(case).geometry, ltca.Material(), ltca.Options(tooth_model="fe")


def _fe_member(case, member, compute=True):
    """The FE data of one member as the LTCA of :func:`case_task` reads it (beveloid/fe/cache.py): from
    the cache, else computed and cached; returns how ("hit", "miss", ...) and seconds.  Without
    ``compute``: whether the cache has an entry for it (True / False; the LTCA recomputes a stale one)."""
    from ..fe import cache

    geom, material, options = _fe_source(case)
    moduli = {"pinion": (material.pinion_e_mpa, material.pinion_nu), "gear": (material.gear_e_mpa, material.gear_nu)}
    args = (geom, member, *moduli[member], options.fe_refinement)
    key = cache.cache_key(*args, coarsen=options.fe_coarsen)
    if not compute:
        return cache.entry_path(key).is_file()
    name = f"FE tooth of the {case.replace('case', 'case ')} {member}"
    _say(f"{name}: first time, about {FE_FIRST_TIME_S} s of CPU; cached after ({cache.cache_dir()})")
    t0 = time.perf_counter()
    _, how = cache.cached_tooth_data(*args, progress=lambda done, total, what: _say(f"{name}: {what.split(': ', 1)[-1]}"),
                                     coarsen=options.fe_coarsen)
    return how, time.perf_counter() - t0


def submit_fe_teeth(tasks, cases, model) -> list:
    """Handles of the FE data of every member of ``cases`` that the cache lacks (none for the plate)."""
    if model != "fe":
        return []
    todo = [(c, m) for c in cases for m in ("pinion", "gear") if not _fe_member(c, m, compute=False)]
    return [tasks.submit(_fe_member, c, m) for c, m in todo]


def case_task(case, out, model):
    """The loaded study of one case: its figures into ``out``; returns (its CSV rows, its table lines,
    its figure lines, seconds)."""
    from pathlib import Path

    from .. import ltca
    from ..ltca.results import plots
    from ..pair import Pair

    t0 = time.perf_counter()
    pair = Pair.example(case)
    g, design = pair.geometry, pair.design
    fig = FIGURES[case]
    out = Path(out)
    rows, lines, results = [], [], []
    for t in TORQUES_NM:
        _say(f"loaded contact {case}, T1 = {t:g} N m")
        r = ltca.analyze(g, ltca.LoadCase(t), ltca.Options(flank=FLANK, positions=POSITIONS, tooth_model=model)).with_patterns()
        results.append(r)
        ok = r.converged
        fr = {m: r.pattern(m).area_fraction for m in ("pinion", "gear")}
        te = r.loaded_te[ok] * 1e6
        share = np.nanmax(r.pair_load_n[ok] / r.pair_load_n[ok].sum(axis=1, keepdims=True)) if ok.any() else np.nan
        row = (case, math.degrees(design.fpd_angle_right), t, t * g.gear.teeth / g.pinion.teeth,
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
    figures = [f"![Fig {fig}](fig{fig}_loaded_contact.png)",
               f"![Fig {fig}, pressure at each position](fig{fig}_loaded_positions.png)"]
    return rows, lines, figures, time.perf_counter() - t0


def finish(out, parts, model):
    """The CSV of both cases and the report's lines, from :func:`case_task`'s results per case."""
    teeth = ("the FE tooth (beveloid/fe: gmsh mesh of each member's sector from the generated geometry, refinement"
             " 1; bending compliance and root stress; docs/loaded_contact.md)" if model == "fe" else
             "the plate tooth (thin slices of the equivalent spur tooth with the plate's face coupling)")
    lines = ["## Loaded contact (Figs 24-25), approximate LTCA", "",
             "Pinion torques T1 (the captions of Figs 24-25 mix pinion and gear torque; here all are pinion "
             f"torques, the gear torque is T2 = T1 N2/N1). Right flank, {cycle_positions_text(POSITIONS)}, the "
             "default grid (cells "
             "sized from each pair's Hertz semi-axes), steel. "
             "Pattern area: the share of the flank (between form limit, tip, toe and heel) that carries "
             "pressure somewhere in the cycle. Model and limits: docs/loaded_contact.md; checks: "
             "docs/validation.md.", "", f"Tooth model: **{model}**, {teeth}.", "",
             "| case | xi_R (deg) | T1 (N m) | T2 (N m) | pinion area | gear area | surface max pressure (MPa) | "
             "loaded TE mean (urad) | loaded TE p-p (urad) | max pair load share | converged | "
             "root stress pinion / gear (MPa) |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    rows, figures, seconds = [], [], 0.0
    for case_rows, case_lines, case_figures, s in parts.values():
        rows += case_rows
        lines += case_lines
        figures += case_figures
        seconds += s
    with open(out / "fig24_fig25_loaded.csv", "w") as f:
        f.write("case,fpd_angle_right_deg,pinion_torque_nm,gear_torque_nm,pinion_area_fraction,gear_area_fraction,"
                "surface_max_pressure_mpa,loaded_te_mean_urad,loaded_te_ptp_urad,max_pair_load_share,converged_positions\n")
        for r in rows:
            f.write(",".join(str(v) for v in r) + "\n")
    lines += [""] + [x for f in figures for x in (f, "")]
    lines += [f"Computed in {seconds:.1f} s of the processes' time, the FE teeth's data aside (data: "
              "fig24_fig25_loaded.csv).", ""]
    return lines


def _pct(v):
    return "-" if v is None else f"{v * 100:.0f}%"

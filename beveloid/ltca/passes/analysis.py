"""``run(geom, errors, torque_nm, options, material, solver) -> LTCAResult``: the loaded TCA of one flank over one mesh cycle.

1. The rigid-body reference (:class:`cycle.Setup`): each pair's tangency, its principal curvature
   axes and curvatures.
2. A first pass on the coarse grid (:meth:`grid.PairGrid.coarsened` counts), each pair's grid
   sized from Hertz for the pair carrying the whole torque: the load of every pair.
3. The result pass: each pair's grid sized from Hertz at its first-pass load
   (:data:`grid.EXTENT_ACROSS`, :data:`grid.EXTENT_ALONG` times the semi-axes); a grid whose
   loaded flank cells reach its outermost rows grows (:data:`grid.GROWTH`, :func:`grid.reaches_edge`) and
   its position is solved again.
4. The convergence indicator: the same extents once coarsened, solved again, compared; its along-columns
   placed where the result grid's lie (resampled, not probed again).  Skipped on request
   (``leave_out`` holding "convergence": nothing else reads it; the result's ``convergence`` is then nan).
Each pass after the first starts its active sets from the previous pass's contact set mapped onto its
grid (:func:`cycle.mapped_contact`): the same solution, in fewer iterations.  The first and the result pass
run in waves (:func:`_torque_after_torque`): a position starts from the same error set's contact set at the
torque before, at the first torque from the first error set's, cell for cell.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np

from ... import tca
from ...mesh import cycle_positions_text
from ...status import LoadedStatus
from ..model import grid as grids
from .cycle import Problem, held_contact, merge, solve_many
from .cycle import setups as cycle_setups
from ..options import Material, Options
from ..results.result import (MAX_HALF_WIDTH_TIMES_CURVATURE, MAX_PRESSURE_OVER_E_STAR, VALIDITY_SEPARATOR, Convergence,
                     LTCAResult)
from ..model.teeth import member_teeth, one_blas_thread, root_stresses


def run(geom, errors, torque_nm: float, options: Options, material: Material, solver, pair=None) -> LTCAResult:
    """The LTCA of ``geom`` (a PairGeometry) with the assembly ``errors``; see the module docstring.
    ``pair``: the Pair when known (the FE tooth reads the bores from its spec).  One case of
    :func:`run_many`."""
    return run_many(geom, [errors], [torque_nm], options, material, solver, pair)[0][0]


def run_many(geom, error_sets, torques_nm, options: Options, material: Material, solver, pair=None,
             leave_out=()) -> list:
    """``[[LTCAResult of error set k at torque t for t in torques_nm] for k in error_sets]``: every
    (error set, torque) case of one pair in one batch.  The teeth once (the FE data once per pair);
    the rigid reference once per error set (it does not depend on the torque); each pass of the module
    docstring once for every case, its contact problems in one compiled call
    (:func:`cycle.solve_many`); the root stresses of every loaded (position, pair) of a case at once.
    ``leave_out``: "convergence": step 4 of the module docstring left out (each result's convergence nan);
    "along_face": no result's ``root_stress_along_face`` (each empty); "compression": no result's
    ``pair_root_compressive_stress_mpa`` (each empty: the other fillet's extreme not sought).
    ``torques_nm``: the torques of every error set, or one sequence of torques per error set (a ragged batch:
    ``[[LTCAResult of set k at each of its torques] for k]``).  ``options.angles``: the pinion angles to
    solve at instead of the mesh cycle's (the rating's refinement of a maximum between positions)."""
    angles = None if options.angles is None else np.asarray(options.angles, dtype=float)
    cycle_text = None if angles is None else f"{angles.size} pinion angle(s) asked within the mesh cycle"
    options.check_memory()
    teeth, body_notes = member_teeth(pair, geom, options, material)
    per_set = ([list(t) for t in torques_nm] if len(torques_nm) and np.ndim(torques_nm[0])
               else [list(torques_nm)] * len(error_sets))
    with one_blas_thread(), np.errstate(all="ignore"):
        setups = cycle_setups(geom, options.flank, error_sets, options.positions, options.pairs, solver, angles)
        cases = [(s, float(t)) for s, ts in zip(setups, per_set) for t in ts]
        results = _run(cases, options, material, teeth, body_notes, leave_out, cycle_text)
    held = geom if pair is None else pair
    results = [dataclasses.replace(r, pair=held) for r in results]  # each holds the pair it was computed for
    ends = np.cumsum([0] + [len(ts) for ts in per_set])
    return [results[a:b] for a, b in zip(ends[:-1], ends[1:])]


def _run(cases, options, material, teeth, body_notes=(), leave_out=(), cycle_text=None):
    """The passes of the module docstring over every (setup, torque) case at once; ``cycle_text``: the
    positions in words (None: the mesh cycle's, ``cycle_positions_text``)."""
    N, P = options.positions, options.pairs
    e_star = material.e_star_mpa
    fine = options.cells
    coarse = (grids.coarser(fine[0]), grids.coarser(fine[1]))

    def sized(setup, cells, load):
        fr, geom = setup.frame, setup.geom
        line = geom.pinion.face_width_mm / max(math.cos(geom.pinion.helix_angle), 0.3)
        b, a = grids.hertz_semi_axes(fr.curvature_across, fr.curvature_along, load, e_star, line)
        fb = np.nanmax(np.where(np.isfinite(b), b, np.nan)) if np.isfinite(b).any() else 0.1 * geom.normal_module_mm
        fa = np.nanmax(np.where(np.isfinite(a), a, np.nan)) if np.isfinite(a).any() else setup.max_along_mm
        return grids.sized(cells, b, a, setup.max_along_mm, np.stack(np.broadcast_arrays(fb, fa), -1)
                           * np.ones((N, P, 1)) * [grids.EXTENT_ACROSS, grids.EXTENT_ALONG])

    def solve_all(problems):
        return solve_many(problems, e_star, teeth)

    every = [s.solved & s.has_reference[:, None] for s, _ in cases]
    full = [s.full_load_n(T) for s, T in cases]
    # 2. first pass: coarse, every pair sized for the whole torque (along: at most the flank's half diagonal)
    g1 = []
    for (s, _), f in zip(cases, full):
        g = sized(s, coarse, f)
        g1.append(g._replace(along_half_mm=np.minimum(g.along_half_mm, 0.5 * s.max_along_mm)))
    first = _torque_after_torque(cases, lambda c, before: Problem(
        *cases[c][:1], g1[c], every[c], cases[c][1], start_cells=None if before is None else held_contact(before)),
        solve_all)
    # 3. result pass, sized from the first pass's loads; along the line no longer than the first
    # pass's loaded patch (a patch cut by the flank ends is shorter than Hertz's)
    need, grids2 = [], []
    for (s, T), f, e, fst in zip(cases, full, every, first):
        load1 = np.where(fst.converged[:, None], fst.pair_load_n(), f)
        need.append(e & ~s.open_pairs(fst.rotation_rad) | (load1 > 0) & e)
        g = sized(s, fine, np.maximum(load1, grids.LOAD_FLOOR * f))
        reach = grids.loaded_along_mm(fst) * grids.PATCH_MARGIN
        grids2.append(g._replace(along_half_mm=np.where(np.isfinite(reach), np.minimum(g.along_half_mm, reach),
                                                        g.along_half_mm)))
    sols = _torque_after_torque(cases, lambda c, before: Problem(
        *cases[c][:1], grids2[c], need[c], cases[c][1], start=first[c],
        start_cells=None if before is None else held_contact(before)), solve_all)
    notes = [[cycle_text or cycle_positions_text(options.positions), *body_notes] for _ in cases]
    active = list(range(len(cases)))
    for attempt in range(grids.MAX_GROWTHS + 1):
        todo = []
        for c in active:
            sol, s = sols[c], cases[c][0]
            loads = sol.pair_load_n()
            total = loads.sum(axis=1, keepdims=True)
            share = loads / np.where(total > 0, total, np.inf)  # each pair's share of its position's load
            hit = grids.reaches_edge(sol.pressure_mpa, sol.gap.in_flank, *fine, share) & sol.converged[:, None, None]
            hit[..., 1] &= sol.grid.along_half_mm < s.max_along_mm
            rows = np.flatnonzero(hit.any(axis=(1, 2)))
            if rows.size == 0:
                continue
            if attempt == grids.MAX_GROWTHS:
                notes[c].append(f"the loaded patch still reaches the grid edge at {rows.size} positions after "
                                f"{grids.MAX_GROWTHS} enlargements: pressures near that edge are truncated")
                continue
            grow = np.where(hit, grids.GROWTH, 1.0)
            g2 = sol.grid._replace(across_half_mm=sol.grid.across_half_mm * grow[..., 0],
                                   along_half_mm=np.minimum(sol.grid.along_half_mm * grow[..., 1], s.max_along_mm))
            todo.append((c, g2, rows, _grown_shifts(sol, g2, hit.any(axis=-1))))
        if not todo:
            break
        grown = solve_all([Problem(cases[c][0], g2, need[c], cases[c][1], rows, start=sols[c], shift_mm=shift)
                           for c, g2, rows, shift in todo])
        for (c, _, rows, _), new in zip(todo, grown):
            sols[c] = merge(sols[c], new, rows)
        active = [c for c, _, _, _ in todo]
    # 4. the convergence indicator
    # (the same extents: the result grid's along-columns, resampled, place it; its contact set starts it)
    checks = solve_all([Problem(s, sol.grid.coarsened(), nd, T, start=sol,
                                shift_mm=grids.resample_along(sol.gap.across_shift_mm, coarse[1]))
                        for (s, T), sol, nd in zip(cases, sols, need)]) if "convergence" not in leave_out else [None] * len(cases)
    out = []
    for (s, T), sol, check, nt in zip(cases, sols, checks, notes):
        fr, geom = s.frame, s.geom
        line = geom.pinion.face_width_mm / max(math.cos(geom.pinion.helix_angle), 0.3)
        hertz_ref = grids.hertz_peak_mpa(fr.curvature_across, fr.curvature_along, sol.pair_load_n(), e_star, line)
        out.append(_result((s, T), options, sol, check, e_star, nt, hertz_ref,
                           root_stresses(teeth, sol, sol.converged, "along_face" not in leave_out,
                                         "compression" not in leave_out)))
    return out


def _torque_after_torque(cases, problem, solve_all) -> list:
    """The Solution of ``problem(c, before)`` (a :class:`cycle.Problem`) for every case c, solved in waves:
    ``before`` is the Solution of the same error set at the torque before c's, and at an error set's first
    torque that of the first error set at that torque (None for the first case), and it starts c's active
    sets cell for cell (:attr:`cycle.Problem.start_cells`): each pass sizes its grids by one rule at every
    torque and error set, so a patch that grows as Hertz's, or moves little between error sets of a tolerance
    box, keeps its cells, and the contact solve settles in fewer iterations (case 1 tilted, 8 error sets at
    100, 200, 400 N m: 3.8 a position in the first pass, 3.9 in the result pass, from the uncoupled estimate
    and the first pass's mapped set; 2.0-2.2 and 2.6-2.9 so started).  The solution does not depend on the
    start."""
    source = [None] * len(cases)
    wave = [0] * len(cases)
    for c in range(1, len(cases)):
        source[c] = c - 1 if cases[c][0] is cases[c - 1][0] else 0
        wave[c] = wave[source[c]] + 1
    out = [None] * len(cases)
    for w in range(max(wave, default=-1) + 1):
        todo = [c for c, v in enumerate(wave) if v == w]
        for c, sol in zip(todo, solve_all([problem(c, None if source[c] is None else out[source[c]]) for c in todo])):
            out[c] = sol
    return out


def _grown_shifts(sol, grown, hit):
    """(N, P, along cells) the column offsets of the ``grown`` grid: for a pair whose patch ran into its
    grid's outermost rows (``hit`` (N, P)), each column centred on its loaded cells (the pressure
    centroid across), the centroids' line continued straight beyond the loaded columns
    (:func:`grids.continued_line`); every other pair's as placed.  The placed offsets are those of the
    unloaded contact, and they fail where the patch is not there: probed, the columns of a pair in edge
    contact centre on its tangency off the flank, and the patch, held at the blank's edge, stays in the
    grid's outermost rows (random design R4-5 of benchmarks/rating_invariance.py); a contact line
    inclined to the grid leaves it across when its columns are held at their ends' offsets (R3-2;
    issue 57)."""
    shift = sol.gap.across_shift_mm.copy()
    centred = grids.loaded_across_centres_mm(sol)[hit]
    centred = np.where(np.isfinite(centred).any(axis=-1, keepdims=True), centred, shift[hit])
    shift[hit] = grids.continued_line(centred[None], sol.grid.along_half_mm[hit][None],
                                      grown.along_half_mm[hit][None])[0]
    return shift


def _peaks(sol):
    """(surface, edge) peak pressure (N, P): cells away from / at a flank edge; nan where none."""
    g = sol.grid
    inner = grids.interior(sol.pressure_mpa, sol.gap.in_flank, g.across_cells, g.along_cells)
    inner = inner.reshape(sol.pressure_mpa.shape)
    p = sol.pressure_mpa
    loaded = p > 0
    surf = np.where(inner, p, -np.inf).max(axis=-1)
    edge = np.where(loaded & ~inner, p, -np.inf).max(axis=-1)
    return np.where(np.isfinite(surf), surf, np.nan), np.where(np.isfinite(edge), edge, np.nan)


def _result(case, options, sol, check, e_star, notes, hertz_ref, root):
    """The LTCAResult of one case from its Solution ``sol``, the indicator's ``check`` (None: not computed)
    and its ``root`` stresses (:func:`root_stresses`)."""
    setup, torque_nm = case  # (the Setup, the torque N m)
    N = options.positions
    ok = sol.converged
    p = sol.pressure_mpa
    area = sol.grid.cell_area_mm2()
    loads = p.sum(axis=-1) * area
    moment = np.einsum("jkc,jk,jkc->j", p, area, np.where(sol.gap.in_flank, sol.gap.pinion_arm_mm, 0.0))
    surface, edge = _peaks(sol)
    total = loads.sum(axis=-1)
    if check is None:  # the indicator not computed (run_many(..., leave_out=("convergence",)))
        dp = dl = np.full(N, np.nan)
    else:
        surface_c, edge_c = _peaks(check)
        loads_c = check.pair_load_n()
        # the surface peaks of pairs clear of the flank edges on both grids (an edge peak is grid-dependent)
        clear = np.isfinite(surface) & np.isfinite(surface_c) & np.isnan(edge) & np.isnan(edge_c)
        dp = np.where(clear, np.abs(surface_c / surface - 1.0), np.nan)
        dp = np.array([np.nanmax(r) if np.isfinite(r).any() else np.nan for r in dp])
        dl = np.where(check.converged & ok, np.abs(loads_c - loads).max(axis=-1) / np.where(total > 0, total, np.nan),
                      np.nan)
    # the model's validity: elastic, small strain
    semi = _semi_minor(sol)
    # every position at once (the string only where a limit is passed): surface peaks only, an edge peak is
    # singular and grid-dependent by nature; and the mean pressure of the whole contact (2/3 of the peak for
    # Hertz), which an edge contact's grid does not change
    lim = MAX_PRESSURE_OVER_E_STAR * e_star
    floor = np.zeros((N, 1))
    contact = ((p > 0) * area[..., None]).sum(axis=(1, 2))
    peak = np.nanmax(np.concatenate([surface, floor], axis=1), axis=1)
    mean = np.where(contact > 0, loads.sum(axis=1) / np.where(contact > 0, contact, 1.0), 0.0)
    strain = np.nanmax(np.concatenate([semi * setup.frame.curvature_across, floor], axis=1), axis=1)
    elastic = ok & ((peak > lim) | (mean > 2 / 3 * lim))
    small = ok & (strain > MAX_HALF_WIDTH_TIMES_CURVATURE)
    validity = []
    for j in range(N):
        why = []
        if elastic[j]:
            why.append(f"pressure beyond the elastic range of gear steels (surface peak > {MAX_PRESSURE_OVER_E_STAR:g}"
                       f" E* = {lim:.0f} MPa or mean > {2 * lim / 3:.0f} MPa)")
        if small[j]:
            why.append(f"patch half-width x curvature > {MAX_HALF_WIDTH_TIMES_CURVATURE:g} (not a small strain)")
        validity.append(VALIDITY_SEPARATOR.join(why) or None)
    gear_rot = setup.gear_sign * sol.rotation_rad
    ref = setup.reference
    te_rigid_ref = (setup.gear_angle - tca.unknowns(ref.x).gear_angle_rad
                    + setup.n1_over_n2 * (setup.phi1 - ref.pinion_angle))
    notes = list(notes) + [
        f"{m}: no root stress at {n} loaded tooth pair(s): every fillet node lies within the FE tooth's reading"
        f" depth of the load (the contact reaches the fillet); the largest root stress is that of the other pairs"
        for m, n in root["unread"].items() if n]
    status = tuple(LoadedStatus.OK if ok[j] else LoadedStatus.NO_CONTACT if sol.no_contact[j]
                   else LoadedStatus.NOT_CONVERGED for j in range(N))
    okc = ok[:, None]
    return LTCAResult(
        options=options, flank=options.flank, torque_nm=torque_nm, pinion_angle=setup.phi1, tooth_pairs=setup.ks,
        status=status, loaded_te=np.where(ok, te_rigid_ref + gear_rot, np.nan), unloaded_te=setup.unloaded_te,
        pair_load_n=np.where(okc, loads, np.nan), pair_max_pressure_mpa=np.where(okc, p.max(axis=-1), np.nan),
        pair_surface_max_pressure_mpa=np.where(okc, surface, np.nan),
        pair_edge_max_pressure_mpa=np.where(okc, edge, np.nan),
        pair_hertz_max_pressure_mpa=np.where(okc & (loads > 0), hertz_ref, np.nan),
        contact_area_mm2=np.where(ok, contact, np.nan),
        pinion_moment_nmm=np.where(ok, moment, np.nan), iterations=sol.iterations,
        complementarity_residual=sol.complementarity_residual, load_residual=sol.load_residual, grid=sol.grid,
        convergence=Convergence(np.where(ok, dp, np.nan), dl), validity=tuple(validity), pressure_mpa=p,
        gap=sol.gap, axes=setup.frame.axes, tangency_unknowns=np.where(setup.solved[..., None], setup.x, np.nan),
        pair_pinion_angle=setup.pair_phi1, notes=tuple(notes), tooth_model=options.tooth_model,
        fe_refinement=options.fe_refinement if options.tooth_model == "fe" else None,
        fe_coarsen=options.fe_coarsen if options.tooth_model == "fe" else None,
        pair_root_stress_mpa=root["tension"], pair_root_compressive_stress_mpa=root["compression"],
        pair_root_stress_where=root["where"], root_stress_along_face=root["along"],
        mesh_stiffness_n_per_um=np.where(ok & (sol.approach_mm > 0), total / (1e3 * sol.approach_mm), np.nan))


def _semi_minor(sol):
    """(N, P) the loaded patch's semi-axis across the contact line, sqrt(5 <x^2>) of the pressure."""
    g = sol.grid
    nx, ny = g.across_cells, g.along_cells
    ux = grids.centres(1.0, nx)
    p = sol.pressure_mpa.reshape(sol.pressure_mpa.shape[:2] + (nx, ny))
    x = ux[None, None, :, None] * g.across_half_mm[..., None, None] + sol.gap.across_shift_mm[:, :, None, :]
    w = p.sum(axis=(-1, -2))
    with np.errstate(all="ignore"):
        mx = (p * x).sum(axis=(-1, -2)) / w
        var = (p * (x - mx[..., None, None]) ** 2).sum(axis=(-1, -2)) / w
    return np.where(w > 0, np.sqrt(5 * var), np.nan)

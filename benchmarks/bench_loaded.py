"""Loaded-contact benchmark: one loaded mesh position with 3 tooth pairs, and a cycle of 20.

    python benchmarks/bench_loaded.py            # table
    python benchmarks/bench_loaded.py --json     # the same numbers as JSON

Not a test.  Runs on one core (BLAS threads are set to 1 before numpy is imported).
Problem: a 20 deg spur pair, m = 4 mm, z = 30/30, face 20 mm, as a stand-in for the
geometry the LTCA will supply later.  Per tooth pair a grid of 20 (profile, over the
active flank from the base circle + 0.5 mm to the tip) x 30 (face) cells; the gap of pair
k is a profile curvature about its contact line plus a 10 um crowning plus a pair offset
(0, 3, 40 um: two pairs share the load, the third stays open).  Compliance per pair: the
Love half-space matrix of the cells plus both teeth's thin-slice matrices with the plate
face coupling (tooth height); the three pairs are one block-diagonal problem with one rigid rotation
(moment weights r_b / r_b = 1 for a spur pair).  Timed separately:
  build   the compliance blocks and their checks (once per grid; the grid is fixed on the flank),
  cold    one solve from the solver's own start set,
  warm    one solve started from the contact set of the previous position,
  cycle   20 positions, contact line moving over the flank, each started from the previous.
Beside them (docs/loaded_contact.md 1, 2, 8.1): one half-space block by the tensor (Toeplitz) builder
against the general one, the checks of `prepare_compliance` against one cold solve, and the tensor
builder on the LTCA's default 11 x 17 grid.
"""
from __future__ import annotations

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_v] = "1"

import argparse  # noqa: E402
import json  # noqa: E402
import math  # noqa: E402
import statistics  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from beveloid.ltca.mechanics.halfspace import (influence_matrix_mm_per_mpa, reduced_modulus_mpa, tensor_grid,  # noqa: E402
                                    tensor_influence_matrix_mm_per_mpa)
from beveloid.ltca.mechanics.lcp import prepare_compliance, solve_contact  # noqa: E402
from beveloid.ltca.mechanics.tooth_compliance import (  # noqa: E402
    face_coupling_per_mm,
    involute_load_points,
    involute_tooth_section,
    slice_compliance_mm2_per_n,
    tooth_influence_mm_per_mpa,
)

MODULE_MM, TEETH, WIDTH_MM = 4.0, 30, 20.0
N_PROFILE, N_FACE, PAIRS = 20, 30, 3
TORQUE_NM = 400.0


def setup(n_profile: int, n_face: int):
    r_p = MODULE_MM * TEETH / 2
    r_b = r_p * math.cos(math.radians(20))
    r_a = r_p + MODULE_MM
    # profile coordinate: roll distance along the line of action, base circle + 0.5 mm to the tip
    rho_lo, rho_hi = math.sqrt((r_b + 0.5) ** 2 - r_b**2), math.sqrt(r_a**2 - r_b**2)
    xe = np.linspace(rho_lo, rho_hi, n_profile + 1)
    ze = np.linspace(0.0, WIDTH_MM, n_face + 1)
    cells = tensor_grid(xe, ze)
    e_star = reduced_modulus_mpa()
    xc = 0.5 * (xe[1:] + xe[:-1])
    section = involute_tooth_section(MODULE_MM, TEETH)
    centre = 2 * r_p * math.sin(math.radians(20))  # sum of both roll distances (z1 = z2)
    pinion = involute_load_points(MODULE_MM, TEETH, np.sqrt(r_b**2 + xc**2))
    # the mating gear point; beyond the gear's tip it is clipped to the tip (stand-in geometry)
    gear = involute_load_points(MODULE_MM, TEETH, np.sqrt(r_b**2 + np.clip(centre - xc, rho_lo, rho_hi) ** 2))
    height = 2.25 * MODULE_MM  # the tooth: the face coupling's plate
    t0 = time.perf_counter()
    k = face_coupling_per_mm(0.5 * (ze[1:] + ze[:-1]), 0.5 * np.diff(ze), WIDTH_MM, height)
    block = tensor_influence_matrix_mm_per_mpa(xe, ze, e_star)
    for lp in (pinion, gear):
        block = block + tooth_influence_mm_per_mpa(slice_compliance_mm2_per_n(section, lp), k, cells.area_mm2)
    compliance = prepare_compliance([block] * PAIRS)  # checked once for all positions
    build_s = time.perf_counter() - t0
    return cells, xc, r_b, compliance, build_s, (xe, ze)


def gap(cells, contact_roll_mm, rho_rel_mm):
    """Gap of the three pairs: profile curvature about each pair's contact line, crowning, offsets."""
    offsets_mm = (0.0, 0.003, 0.040)
    base_pitch = math.pi * MODULE_MM * math.cos(math.radians(20))
    crown = 0.010 * ((cells.y_mm - WIDTH_MM / 2) / (WIDTH_MM / 2)) ** 2
    parts = []
    for k, off in enumerate(offsets_mm):
        x0 = contact_roll_mm + (k - 1) * base_pitch * 0.35  # pairs' contact lines spread over the flank
        parts.append((cells.x_mm - x0) ** 2 / (2 * rho_rel_mm) + crown + off)
    return np.concatenate(parts)


def _best_ms(fn, repeats: int) -> float:
    best = math.inf
    for _ in range(max(3, repeats // 4)):
        t = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t)
    return 1e3 * best


def side_timings(cells, edges, blocks, repeats: int) -> dict:
    """The builders and the checks, best of a few runs each (ms)."""
    e_star = reduced_modulus_mpa()
    xe, ze = edges
    small_x, small_y = np.linspace(-0.2, 0.2, 12), np.linspace(-3.0, 3.0, 18)  # 11 x 17 cells
    raw = [np.asarray(b) for b in blocks.blocks]
    return {
        "block_cells": int(cells.x_mm.size),
        "tensor_build_ms": _best_ms(lambda: tensor_influence_matrix_mm_per_mpa(xe, ze, e_star), repeats),
        "general_build_ms": _best_ms(lambda: influence_matrix_mm_per_mpa(cells, e_star), 4),
        "prepare_ms": _best_ms(lambda: prepare_compliance(raw), repeats),
        "ltca_grid_build_ms": _best_ms(lambda: tensor_influence_matrix_mm_per_mpa(small_x, small_y, e_star), repeats),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--repeats", type=int, default=20)
    ap.add_argument("--profile-cells", type=int, default=N_PROFILE)
    ap.add_argument("--face-cells", type=int, default=N_FACE)
    args = ap.parse_args()

    cells, xc, r_b, blocks, build_s, edges = setup(args.profile_cells, args.face_cells)
    area = np.tile(cells.area_mm2, PAIRS)
    load_n = TORQUE_NM * 1e3 / r_b  # torque about the pinion axis over the base radius
    rho_rel = 0.5 * (MODULE_MM * TEETH / 2) * math.sin(math.radians(20))
    mid = float(xc.mean())
    positions = np.linspace(mid - 1.5, mid + 1.5, 20)

    def run(h, start=None):
        t = time.perf_counter()
        sol = solve_contact(blocks, h, area, load_n, initial_contact=start)
        return time.perf_counter() - t, sol

    h0, h1 = gap(cells, positions[9], rho_rel), gap(cells, positions[10], rho_rel)
    run(h0)  # warm-up (first-call overheads in scipy)
    cold = [run(h0) for _ in range(args.repeats)]
    prev = cold[0][1]
    warm = [run(h1, prev.in_contact) for _ in range(args.repeats)]
    cycles = []
    for _ in range(max(3, args.repeats // 4)):
        t = time.perf_counter()
        start, its, ok = None, [], True
        for x in positions:
            _, sol = run(gap(cells, x, rho_rel), start)
            start = sol.in_contact
            its.append(sol.iterations)
            ok &= sol.converged
        cycles.append((time.perf_counter() - t, its, ok))
    sol = cold[0][1]
    pair_load = (area * sol.pressure_mpa).reshape(PAIRS, -1).sum(axis=1)
    builders = side_timings(cells, edges, blocks, args.repeats)
    out = {
        "cells": int(area.size),
        "grid": f"{PAIRS} x {args.profile_cells} x {args.face_cells}",
        "build_ms": 1e3 * build_s,
        "cold_solve_ms": 1e3 * statistics.median(t for t, _ in cold),
        "cold_iterations": sol.iterations,
        "warm_solve_ms": 1e3 * statistics.median(t for t, _ in warm),
        "warm_iterations": warm[0][1].iterations,
        "cycle_20_ms": 1e3 * statistics.median(t for t, _, _ in cycles),
        "cycle_iterations_max": max(max(i) for _, i, _ in cycles),
        "all_converged": bool(all(s.converged for _, s in cold + warm) and all(ok for _, _, ok in cycles)),
        "cells_in_contact": int(sol.in_contact.sum()),
        "pair_load_n": [round(float(v), 3) for v in pair_load],
        "max_pressure_mpa": sol.max_pressure_mpa,
        "complementarity_residual": sol.complementarity_residual,
        "load_residual": sol.load_residual,
        **builders,
    }
    if args.json:
        print(json.dumps(out, indent=2))
        return
    print(f"loaded contact, {out['grid']} = {out['cells']} cells, torque {TORQUE_NM} Nm, one core")
    print(f"  build compliance (once per grid)  {out['build_ms']:8.1f} ms")
    print(f"  solve, cold start                 {out['cold_solve_ms']:8.2f} ms  ({out['cold_iterations']} iterations)")
    print(f"  solve, warm start                 {out['warm_solve_ms']:8.2f} ms  ({out['warm_iterations']} iterations)")
    print(f"  cycle of 20 positions, warm       {out['cycle_20_ms']:8.1f} ms  (max {out['cycle_iterations_max']} iterations)")
    print(f"  cells in contact {out['cells_in_contact']}, pair loads {out['pair_load_n']} N, "
          f"p_max {out['max_pressure_mpa']:.0f} MPa")
    print(f"  residuals: complementarity {out['complementarity_residual']:.1e}, load {out['load_residual']:.1e}; "
          f"all converged: {out['all_converged']}")
    print(f"  one half-space block of {out['block_cells']} cells: tensor builder {out['tensor_build_ms']:.2f} ms, "
          f"general builder {out['general_build_ms']:.1f} ms")
    print(f"  prepare_compliance (the checks) of the {PAIRS} blocks {out['prepare_ms']:.1f} ms")
    print(f"  tensor builder on the LTCA's default 11 x 17 grid {out['ltca_grid_build_ms']:.3f} ms")


if __name__ == "__main__":
    main()

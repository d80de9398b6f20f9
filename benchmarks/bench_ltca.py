"""LTCA benchmark on the paper's case 1 (right flank, 3 tooth pairs, default grid 13 x 31 per pair).

    python benchmarks/bench_ltca.py [--torque-nm 200] [--case case1] [--repeats 5] [--json]

Not a test.  One core: BLAS threads are set to 1 before numpy is imported (without this, on
the shared 2-core machine, OpenBLAS threads make the small solves several times slower).
Timed, median of --repeats (after one warm-up run that also loads numba's cache):
  position   one mesh position, 3 pairs: build the gap from the surfaces, the tooth
             compliance, solve (the grid extent fixed at the one analyze() chose)
  cycle      20 positions, the same three steps (gap included)
  gap        the gap of the 20 positions alone
  analyze    ltca.analyze end to end: the rigid TCA reference, the principal axes, the grid
             sizing on three positions and the cycle (with any regrid)
  pattern    the max-pressure pattern and area fraction on both flanks
"""
from __future__ import annotations

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_v] = "1"

import argparse  # noqa: E402
import json  # noqa: E402
import statistics  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from beveloid import ltca, tca  # noqa: E402
from beveloid.design import design  # noqa: E402
from beveloid.spec import load_example  # noqa: E402


def _median_time(fn, repeats):
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--torque-nm", type=float, default=200.0)
    ap.add_argument("--case", default="case1")
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args()
    g = tca.PairGeometry.from_design(design(load_example(a.case)))
    grid = ltca.GridOptions()
    r = ltca.analyze(g, a.torque_nm, "right", positions=20)  # warm-up, and the grid extent
    xe, ye = ltca._edges(r.across_half_mm, grid.across_cells), ltca._edges(r.along_half_mm, grid.along_cells)
    setup = ltca._Setup(g, "right", np.zeros(5), 20, 3)
    tp = ltca._member_tooth(g, "pinion", 206e3, 0.3)
    tg = ltca._member_tooth(g, "gear", 206e3, 0.3)
    mat = ltca.Material()
    out = {
        "case": a.case, "torque_nm": a.torque_nm, "cells_per_pair": grid.across_cells * grid.along_cells,
        "across_half_mm": r.across_half_mm, "along_half_mm": r.along_half_mm,
        "position_s": _median_time(lambda: ltca._solve_cycle(setup, xe, ye, a.torque_nm, mat, tp, tg, only=[10]),
                                   a.repeats),
        "cycle_20_s": _median_time(lambda: ltca._solve_cycle(setup, xe, ye, a.torque_nm, mat, tp, tg), a.repeats),
        "gap_20_s": _median_time(lambda: setup.gap(xe, ye), a.repeats),
        "analyze_20_s": _median_time(lambda: ltca.analyze(g, a.torque_nm, "right", positions=20), a.repeats),
        "pattern_s": _median_time(lambda: [ltca.flank_pattern(r, g, m) for m in ("pinion", "gear")], a.repeats),
        "iterations_max": int(r.iterations.max()), "all_converged": bool(r.converged.all()),
    }
    if a.json:
        print(json.dumps(out))
        return
    print(f"LTCA {a.case}, right flank, pinion torque {a.torque_nm:g} N m, 3 pairs x {out['cells_per_pair']} cells,"
          f" grid +-{r.across_half_mm:.3f} x +-{r.along_half_mm:.2f} mm, one core, median of {a.repeats}")
    for key, label in (("position_s", "one position (gap + teeth + solve)"), ("cycle_20_s", "cycle of 20 positions"),
                       ("gap_20_s", "  of which the gap of 20 positions"), ("analyze_20_s", "analyze(), 20 positions"),
                       ("pattern_s", "patterns on both flanks")):
        print(f"  {label:40s} {out[key] * 1e3:8.1f} ms")
    print(f"  solver iterations max {out['iterations_max']}, all converged: {out['all_converged']}")


if __name__ == "__main__":
    main()

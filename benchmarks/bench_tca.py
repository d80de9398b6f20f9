"""TCA benchmark: batched solver vs a per-point fsolve baseline, measured in one run.

    python benchmarks/bench_tca.py            # table
    python benchmarks/bench_tca.py --json     # {"W1": {...}, "W2": {...}, "import": {...}}

Not a test.  Workloads:
  W1  case 1, aligned, both flanks, 3 tooth pairs x 200 positions: one mesh study end to end
      after import (design + TCA + backlash).  Reported warm (median of repeats) and cold (the
      first call in this process, which also loads numba's compiled cache).
  W2  10,000 random error sets x 50 positions, one flank (the sweep), on one core.
Baseline (same process, >= 200 points): scipy.optimize.fsolve per point on the same five
equations, built with sympy.lambdify(cse=False) from the derivations, Jacobian by fsolve's own
differences, each point warm-started from the previous one.
"""
from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def _baseline_fn(geom, flank):
    """sympy.lambdify(cse=False) of Eq 38 composed from the derivations (as a researcher would)."""
    import sympy as sp

    from beveloid.derivations import kernels

    f, unknowns, phi1, errors, s1, s2, sp_ = kernels.composed_residual(geom.pinion.tooth_surface,
                                                                      geom.gear.tooth_surface, flank)
    fn = sp.lambdify(unknowns + [phi1] + errors + s1 + s2 + sp_, list(f), modules="numpy", cse=False)
    params = (list(geom.surface_params("pinion")[:len(s1)]) + list(geom.surface_params("gear")[:len(s2)])
              + list(geom.placement()))
    return fn, params


def baseline(geom, flank, errors_list, phi_grid, x_start):
    """fsolve per point, warm-started along each path; returns (us_per_point, points, converged)."""
    from scipy.optimize import fsolve

    f, params = _baseline_fn(geom, flank)
    n = 0
    conv = 0
    t0 = time.perf_counter()
    for e, x0 in zip(errors_list, x_start):
        x = np.array(x0, float)
        for phi in phi_grid:
            sol, info, ier, msg = fsolve(lambda z: f(*z, phi, *e, *params), x, full_output=True, xtol=1e-13)
            n += 1
            if ier == 1:
                conv += 1
                x = sol
    return (time.perf_counter() - t0) / n * 1e6, n, conv


def run(repeats=5):
    t_imp = time.perf_counter()
    from beveloid import sweep, tca
    from beveloid.solver import backends
    from beveloid.design import design
    from beveloid.spec import load_spec

    import_all = time.perf_counter() - t_imp
    out = {}
    spec = load_spec(ROOT / "examples" / "case1.toml")

    # ---- W1 -------------------------------------------------------------------------------
    def w1():
        g = tca.PairGeometry.from_design(design(spec))
        return g, tca.analyze(g, positions=200, pairs=3)

    t = time.perf_counter()
    geom, res = w1()
    cold = time.perf_counter() - t
    times = []
    for _ in range(repeats):
        tca.reference_contact.cache_clear()
        t = time.perf_counter()
        geom, res = w1()
        times.append(time.perf_counter() - t)
    warm = statistics.median(times)
    n_w1 = sum(len(fr.status) for fr in res.flanks.values())
    it_w1 = float(np.mean(np.concatenate([fr.iterations for fr in res.flanks.values()])))
    # baseline on >= 200 points of the same study (right flank, aligned, pair 0)
    ref = tca.reference_contact(geom, "right")
    grid = ref.pinion_angle + np.linspace(-1.0, 1.0, 220) * geom.pitch_angles[0]
    b_us, b_n, b_conv = baseline(geom, "right", [np.zeros(5)], grid, [ref.x])
    us = warm / n_w1 * 1e6
    out["W1"] = {"seconds_warm": warm, "seconds_cold_first_call": cold, "points": n_w1, "us_per_point": us,
                 "newton_iterations_mean": it_w1, "baseline_us_per_point": b_us, "baseline_points": b_n,
                 "baseline_converged": b_conv, "speedup": b_us / us, "target_seconds": 0.020}

    # ---- W2 -------------------------------------------------------------------------------
    K, N = 10_000, 50
    backend = tca.resolve_backend("auto")
    if backends.AVAILABLE:
        import numba

        numba.set_num_threads(1)
    sweep.sweep(geom, "right", samples=50, positions=N, seed=1, backend=backend)  # warm-up
    t = time.perf_counter()
    r = sweep.sweep(geom, "right", samples=K, positions=N, seed=0, backend=backend)
    wall = time.perf_counter() - t
    us2 = wall / r.contact_points_solved * 1e6  # the whole sweep, statistics included
    errs = sweep.draw_errors(5, seed=0)
    grid2 = r.pinion_angles
    # the baseline marches each path from its first grid point: start it from the nearest solution
    Xs = tca.solve_grid(geom, "right", errs, grid2[:1], "numpy").x
    b2_us, b2_n, b2_conv = baseline(geom, "right", errs, grid2, Xs[:, 0])
    out["W2"] = {"samples": K, "positions": N, "points": r.contact_points_solved, "seconds": wall,
                 "solve_seconds": r.seconds, "solve_us_per_point": r.seconds / r.contact_points_solved * 1e6,
                 "backend": backend, "threads": 1, "us_per_point": us2,
                 "newton_iterations_mean": r.newton_iterations_mean, "baseline_us_per_point": b2_us,
                 "baseline_points": b2_n, "baseline_converged": b2_conv, "speedup": b2_us / us2,
                 "target_us_per_point": 3.0, "target_speedup": 300}
    if backends.AVAILABLE:
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
        t = time.perf_counter()
        r2 = sweep.sweep(geom, "right", samples=K, positions=N, seed=0, backend=backend)
        out["W2"]["us_per_point_all_threads"] = (time.perf_counter() - t) / r2.contact_points_solved * 1e6
        out["W2"]["threads_all"] = numba.config.NUMBA_NUM_THREADS
    # numpy fallback on the same workload, for the record (smaller K: same per-point cost)
    t = time.perf_counter()
    rn = sweep.sweep(geom, "right", samples=200, positions=N, seed=0, backend="numpy")
    out["W2"]["numpy_us_per_point"] = (time.perf_counter() - t) / rn.contact_points_solved * 1e6

    # ---- import --------------------------------------------------------------------------
    code = "import time; t=time.perf_counter(); import beveloid; print(time.perf_counter()-t)"
    imp = [float(subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                                check=True).stdout) for _ in range(5)]
    code2 = ("import time; t=time.perf_counter(); import beveloid.tca, beveloid.design, beveloid.sweep; "
             "print(time.perf_counter()-t)")
    imp2 = [float(subprocess.run([sys.executable, "-c", code2], capture_output=True, text=True,
                                 check=True).stdout) for _ in range(5)]
    out["import"] = {"import_beveloid_s": statistics.median(imp), "import_runtime_modules_s": statistics.median(imp2),
                     "target_s": 0.3, "in_this_process_s": import_all}
    return out


def table(o):
    w1, w2, im = o["W1"], o["W2"], o["import"]
    rows = [
        ("workload", "us/point", "Newton it.", "baseline us/point", "speedup", "target", "met"),
        ("W1 mesh study (warm)", f"{w1['us_per_point']:.2f}", f"{w1['newton_iterations_mean']:.2f}",
         f"{w1['baseline_us_per_point']:.0f}", f"{w1['speedup']:.0f}x",
         f"<= 20 ms (got {w1['seconds_warm'] * 1e3:.1f} ms; cold {w1['seconds_cold_first_call'] * 1e3:.0f} ms)",
         "yes" if w1["seconds_warm"] <= 0.020 else "no"),
        ("W2 sweep, 1 core", f"{w2['us_per_point']:.2f}", f"{w2['newton_iterations_mean']:.2f}",
         f"{w2['baseline_us_per_point']:.0f}", f"{w2['speedup']:.0f}x", "<= 3 us/point, >= 300x",
         "yes" if w2["us_per_point"] <= 3 and w2["speedup"] >= 300 else "no"),
        ("import beveloid", f"{im['import_beveloid_s'] * 1e3:.1f} ms", "", "", "", "<= 300 ms",
         "yes" if im["import_beveloid_s"] <= 0.3 else "no"),
    ]
    w = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    lines = ["  ".join(c.ljust(wi) for c, wi in zip(r, w)) for r in rows]
    extra = [f"W2 solve loop alone: {w2['solve_us_per_point']:.2f} us/point (the rest: window, aligned path, statistics)",
             f"W2 all threads ({w2.get('threads_all', 1)}): {w2.get('us_per_point_all_threads', float('nan')):.2f} us/point;"
             f" numpy fallback: {w2['numpy_us_per_point']:.2f} us/point; backend {w2['backend']}",
             f"import of the runtime modules (tca, design, sweep): {im['import_runtime_modules_s'] * 1e3:.0f} ms",
             f"baselines: {w1['baseline_points']} + {w2['baseline_points']} points, "
             f"{w1['baseline_converged']} + {w2['baseline_converged']} converged"]
    return "\n".join(lines + [""] + extra)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args()
    o = run()
    print(json.dumps(o, indent=2) if a.json else table(o))


if __name__ == "__main__":
    main()

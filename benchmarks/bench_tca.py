"""TCA benchmark: batched solver vs a per-point fsolve baseline, measured in one run.

    python benchmarks/bench_tca.py            # table
    python benchmarks/bench_tca.py --json     # {"W1": {...}, "W2": {...}, "W3": {...}, "import": {...}}
    python benchmarks/bench_tca.py --only sweeps  # W2 and W3 only
    python benchmarks/bench_tca.py --only micro   # W3 and W4 only
    python benchmarks/bench_tca.py --only mesh    # W1 only
    python benchmarks/bench_tca.py --cpu-time     # the process's CPU time instead of wall time
    PYTHONPATH=/tmp/base python benchmarks/bench_tca.py --json --cpu-time   # another checkout's code

Not a test.  Workloads:
  W1  case 1, aligned, both flanks, 3 tooth pairs x 200 positions: one mesh study end to end
      after import (design + TCA + backlash).  Reported warm (median of repeats, every
      per-geometry cache cleared before each) and cold (the first call in this process, which
      also loads numba's compiled cache).
  W2  10,000 random error sets x 50 positions, one flank (the sweep), on one core.
  W3  W2 on crowned flanks: case 1 with C_alpha = C_beta = 20 um on both members (issue 10).
  W4  W3 plus tip relief (30 um over 0.4 m_n) and end relief (40 um over 0.2 W) on both members (issue 20).
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
#: the clock of every timed workload: wall time, or this process's CPU time (--cpu-time: what a
#: machine shared with other jobs leaves comparable between two runs)
_CLOCK = {"clock": time.perf_counter}


def clock() -> float:
    return _CLOCK["clock"]()


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
    t0 = clock()
    for e, x0 in zip(errors_list, x_start):
        x = np.array(x0, float)
        for phi in phi_grid:
            sol, info, ier, msg = fsolve(lambda z: f(*z, phi, *e, *params), x, full_output=True, xtol=1e-13)
            n += 1
            if ier == 1:
                conv += 1
                x = sol
    return (clock() - t0) / n * 1e6, n, conv


def sweep_workload(geom, K=10_000, N=50, with_baseline=True):
    """W2/W3: K random error sets x N positions, right flank, one core, the whole sweep call timed;
    the fsolve baseline on 5 of the error sets, from the same solutions' first points."""
    from beveloid import sweep, tca
    from beveloid.solver import Solver, backends

    solver = Solver()
    backend = solver.backend
    if backends.AVAILABLE:
        import numba

        numba.set_num_threads(1)
    sweep.analyze(geom, sweep.Options(flank="right", samples=50, positions=N, seed=1), solver=solver)  # warm-up
    t = clock()
    r = sweep.analyze(geom, sweep.Options(flank="right", samples=K, positions=N, seed=0), solver=solver)
    wall = clock() - t
    us = wall / r.contact_points_solved * 1e6  # the whole sweep, statistics included
    errs = sweep.draw_errors(5, seed=0)
    grid = r.pinion_angles
    # the baseline marches each path from its first grid point: start it from the nearest solution
    if with_baseline:
        Xs = tca.solve_grid(geom, "right", errs, grid[:1], solver=Solver("numpy")).x
        b_us, b_n, b_conv = baseline(geom, "right", errs, grid, Xs[:, 0])
    else:  # (W4: the explicit micro-geometry normal is too large a tree for the lambdify baseline)
        b_us, b_n, b_conv = float("nan"), 0, 0
    out = {"samples": K, "positions": N, "points": r.contact_points_solved, "seconds": wall,
           "solve_seconds": r.seconds, "solve_us_per_point": r.seconds / r.contact_points_solved * 1e6,
           "backend": backend, "threads": 1, "us_per_point": us,
           "newton_iterations_mean": r.newton_iterations_mean, "baseline_us_per_point": b_us,
           "baseline_points": b_n, "baseline_converged": b_conv, "speedup": b_us / us,
           "status_counts": r.to_json()["status_counts"]}
    if backends.AVAILABLE:
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
        t = clock()
        r2 = sweep.analyze(geom, sweep.Options(flank="right", samples=K, positions=N, seed=0), solver=solver)
        out["us_per_point_all_threads"] = (clock() - t) / r2.contact_points_solved * 1e6
        out["threads_all"] = numba.config.NUMBA_NUM_THREADS
    # numpy fallback on the same workload, for the record (smaller K: same per-point cost)
    t = clock()
    rn = sweep.analyze(geom, sweep.Options(flank="right", samples=200, positions=N, seed=0), solver=Solver("numpy"))
    out["numpy_us_per_point"] = (clock() - t) / rn.contact_points_solved * 1e6
    return out


def crowned_case1(amount_um=20.0):
    """W3's pair: case 1 with C_alpha = C_beta = amount_um on both members."""
    from beveloid.studies.crowning import crowned_geometry

    return crowned_geometry("case1", amount_um)


def micro_case1():
    """W4's pair: W3's crowning (20/20 um) plus the micro-geometry study's tip relief (30 um over
    0.4 m_n) and end relief (40 um over 0.2 of the face) on both members (issue 20)."""
    import dataclasses

    from beveloid.studies.micro_geometry import modified

    geom = modified(crowned_case1())
    def crowned(m):
        return dataclasses.replace(m, surface_options=tuple(sorted(
            {**dict(m.surface_options), "profile_crowning_um": 20.0, "lead_crowning_um": 20.0}.items())))
    return dataclasses.replace(geom, pinion=crowned(geom.pinion), gear=crowned(geom.gear))


def run(repeats=5, only=None):
    if only == "micro":  # W3 and W4 in one run (issue 20: W4 <= 1.5 x W3 per point)
        return {"W3": dict(sweep_workload(crowned_case1()), target_us_per_point=3.0, target_speedup=1000,
                           crowning_um=20.0),
                "W4": dict(sweep_workload(micro_case1(), with_baseline=False), crowning_um=20.0, tip_relief_um=30.0,
                           end_relief_um=40.0)}
    if only == "sweeps":  # W2 and W3 only, in one run (their ratio is what a noisy machine keeps)
        from beveloid.pair import Pair

        geom = Pair.from_spec(ROOT / "examples" / "case1.toml").geometry
        return {"W2": dict(sweep_workload(geom), target_us_per_point=3.0, target_speedup=300),
                "W3": dict(sweep_workload(crowned_case1()), target_us_per_point=3.0, target_speedup=1000,
                           crowning_um=20.0)}
    t_imp = time.perf_counter()
    from beveloid import sweep, tca  # noqa: F401  (timed: the import of the runtime)
    from beveloid.solver import patch_cover
    from beveloid.solver import backends  # noqa: F401
    from beveloid.design import design
    from beveloid.spec import load_spec

    import_all = time.perf_counter() - t_imp
    out = {}
    spec = load_spec(ROOT / "examples" / "case1.toml")

    # ---- W1 -------------------------------------------------------------------------------
    def w1():
        g = tca.PairGeometry.from_design(design(spec))
        return g, tca.analyze(g, tca.Options(positions=200, pairs=3, approach_mm=None))

    t = clock()
    geom, res = w1()
    cold = clock() - t
    times = []
    for _ in range(repeats):
        # a new design pays for every per-geometry cache: the reference contacts, the first-touch
        # signs, the whole pitches of the backlash and the pinion patch covers
        for cached in (tca.reference_contact, tca.first_touch_sign, tca.whole_pitches, patch_cover.patch_cover):
            cached.cache_clear()
        t = clock()
        geom, res = w1()
        times.append(clock() - t)
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

    if only == "mesh":
        return out

    # ---- W2, W3 ---------------------------------------------------------------------------
    out["W2"] = dict(sweep_workload(geom), target_us_per_point=3.0, target_speedup=300)
    out["W3"] = dict(sweep_workload(crowned_case1()), target_us_per_point=3.0, target_speedup=1000,
                     crowning_um=20.0)

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


def _sweep_row(name, w, target):
    return (name, f"{w['us_per_point']:.2f}", f"{w['newton_iterations_mean']:.2f}", f"{w['baseline_us_per_point']:.0f}",
            f"{w['speedup']:.0f}x", f"<= 3 us/point, >= {target}x",
            "yes" if w["us_per_point"] <= 3 and w["speedup"] >= target else "no")


def _sweep_extra(name, w):
    return [f"{name} solve loop alone: {w['solve_us_per_point']:.2f} us/point (the rest: window, aligned path, statistics)",
            f"{name} all threads ({w.get('threads_all', 1)}): {w.get('us_per_point_all_threads', float('nan')):.2f}"
            f" us/point; numpy fallback: {w['numpy_us_per_point']:.2f} us/point; backend {w['backend']}",
            f"{name} statuses: " + ", ".join(f"{k} {v}" for k, v in w["status_counts"].items())]


def table(o):
    head = ("workload", "us/point", "Newton it.", "baseline us/point", "speedup", "target", "met")
    if set(o) == {"W3", "W4"}:
        ratio = o["W4"]["us_per_point"] / o["W3"]["us_per_point"]
        rows = [head, _sweep_row("W3 crowned sweep, 1 core", o["W3"], 1000),
                ("W4 crowned + relieved sweep, 1 core", f"{o['W4']['us_per_point']:.2f}",
                 f"{o['W4']['newton_iterations_mean']:.2f}", "-", "-", "<= 1.5 x W3", "yes" if ratio <= 1.5 else "no")]
        w = [max(len(r[i]) for r in rows) for i in range(len(head))]
        return "\n".join(["  ".join(c.ljust(wi) for c, wi in zip(r, w)) for r in rows] + [""]
                         + _sweep_extra("W3", o["W3"]) + _sweep_extra("W4", o["W4"]) + [f"W4 / W3 per point: {ratio:.2f}"])
    if set(o) == {"W2", "W3"}:
        rows = [head, _sweep_row("W2 sweep, 1 core", o["W2"], 300), _sweep_row("W3 crowned sweep, 1 core", o["W3"], 1000)]
        w = [max(len(r[i]) for r in rows) for i in range(len(head))]
        return "\n".join(["  ".join(c.ljust(wi) for c, wi in zip(r, w)) for r in rows] + [""]
                         + _sweep_extra("W2", o["W2"]) + _sweep_extra("W3", o["W3"])
                         + [f"W3 / W2 per point: {o['W3']['us_per_point'] / o['W2']['us_per_point']:.2f}",
                            f"baselines: {o['W2']['baseline_points']} + {o['W3']['baseline_points']} points, "
                            f"{o['W2']['baseline_converged']} + {o['W3']['baseline_converged']} converged"])
    w1 = o["W1"]
    w1_row = ("W1 mesh study (warm)", f"{w1['us_per_point']:.2f}", f"{w1['newton_iterations_mean']:.2f}",
         f"{w1['baseline_us_per_point']:.0f}", f"{w1['speedup']:.0f}x",
         f"<= 20 ms (got {w1['seconds_warm'] * 1e3:.1f} ms; cold {w1['seconds_cold_first_call'] * 1e3:.0f} ms)",
         "yes" if w1["seconds_warm"] <= 0.020 else "no")
    if set(o) == {"W1"}:
        return "\n".join("  ".join(c.ljust(len(h)) for c, h in zip(r, head)) for r in (head, w1_row)) + (
            f"\nW1 points: {w1['points']}; baseline: {w1['baseline_points']} points, {w1['baseline_converged']} converged")
    w2, w3, im = o["W2"], o["W3"], o["import"]
    rows = [
        head,
        w1_row,
        _sweep_row("W2 sweep, 1 core", w2, 300),
        _sweep_row("W3 crowned sweep, 1 core", w3, 1000),
        ("import beveloid", f"{im['import_beveloid_s'] * 1e3:.1f} ms", "", "", "", "<= 300 ms",
         "yes" if im["import_beveloid_s"] <= 0.3 else "no"),
    ]
    w = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    lines = ["  ".join(c.ljust(wi) for c, wi in zip(r, w)) for r in rows]
    extra = (_sweep_extra("W2", w2) + _sweep_extra("W3", w3)
             + [f"import of the runtime modules (tca, design, sweep): {im['import_runtime_modules_s'] * 1e3:.0f} ms",
                f"baselines: {w1['baseline_points']} + {w2['baseline_points']} + {w3['baseline_points']} points, "
                f"{w1['baseline_converged']} + {w2['baseline_converged']} + {w3['baseline_converged']} converged"])
    return "\n".join(lines + [""] + extra)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--only", choices=("sweeps", "mesh", "micro"),
                    help="sweeps: run only W2 and W3; mesh: only W1; micro: W3 and W4")
    ap.add_argument("--cpu-time", action="store_true",
                    help="time with this process's CPU time (one thread) instead of wall time")
    a = ap.parse_args()
    if a.cpu_time:
        _CLOCK["clock"] = time.process_time
    o = run(only=a.only)
    print(json.dumps(o, indent=2) if a.json else table(o))


if __name__ == "__main__":
    main()

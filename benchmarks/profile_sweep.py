"""Where the compiled sweep's time goes: per-point cost of each piece, on one core.

    python benchmarks/profile_sweep.py
    python benchmarks/profile_sweep.py --crowned 20   # W3's pair: both members crowned by 20 um
    python benchmarks/profile_sweep.py --counts 100   # also: calls per point, numpy backend, 100 sets

Times, for the W2 workload's points (case 1, right flank), each the best of --repeats timed loops
of 50,000 calls (the machine is shared: the best is the least disturbed): one evaluation of the
composed contact system (two surface jets + the Eq 38 assembly, with Jacobians), one evaluation
of an edge and of a corner candidate system (edge_contact.py: boundary jets, second derivatives,
the edge tangency row), the 5x5 solve, the flank-boundary check (margins from the surface points
the evaluation left behind), and the whole compiled path loop.

--counts K runs K error sets of the same sweep on the numpy backend (the core's functions as
they are) and counts how often each piece is called per point: with the times above, where the
loop's time goes.  Not a test.
"""
import collections
import time
from pathlib import Path

import numba
import numpy as np

from beveloid import sweep, tca
from beveloid.solver import Solver, backends, core
from beveloid.pair import Pair

ROOT = Path(__file__).resolve().parents[1]
CORE = backends.namespace("compiled")  # the solver core's own compiled functions
CALLS = 50_000
#: core functions counted by --counts
COUNTED = ("evaluate_unchecked", "evaluate_candidate", "solve_linear", "contact_margin_point", "multipliers",
           "newton_candidate", "first_touch", "follow_edge", "solve_off_patch", "enumerate_candidates",
           "patches_apart")


def _best(fn, args, repeats):
    fn(*args, 10)
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        fn(*args, CALLS)
        times.append(time.perf_counter() - t)
    return min(times) / CALLS


def _loops():
    evaluate, candidate, solve, margin_fn = (CORE.evaluate, CORE.evaluate_candidate, CORE.solve_linear,
                                             CORE.contact_margin_point)
    scratch, edge_scratch = CORE.scratch, CORE.edge_scratch

    @numba.njit
    def evals(problem, x, phi, e, n):
        w = scratch()
        s = 0.0
        for i in range(n):
            evaluate(problem, x, phi + 1e-12 * i, e, w.system)
            s += w.system.F[0]
        return s

    @numba.njit
    def candidates(problem, first, second, x, phi, e, n):
        es = edge_scratch()
        s = 0.0
        for i in range(n):
            candidate(problem, first, second, x, phi + 1e-12 * i, e, es.system)
            s += es.system.F[0]
        return s

    @numba.njit
    def solves(J, F, n):
        out = np.empty(5)
        s = 0.0
        for _ in range(n):
            F[0] += 1e-12
            solve(J, F, out)
            s += out[0]
        return s

    @numba.njit
    def margins(problem, x, phi, e, n):
        w = scratch()
        evaluate(problem, x, phi, e, w.system)
        s = 0.0
        for _ in range(n):
            x[0] += 1e-12
            m, _ = margin_fn(x, problem.pinion_blank, problem.gear_blank, w.system.ws)
            s += m
        return s

    return evals, candidates, solves, margins


def counts(geom, sets):
    """Calls of the COUNTED core functions per point of a `sets` x 50 sweep, numpy backend."""
    tally = collections.Counter()
    saved = {name: getattr(core, name) for name in COUNTED}

    def counted(name, fn):
        def wrapper(*args):
            tally[name] += 1
            return fn(*args)
        return wrapper

    errors = sweep.draw_errors(sets, None, 0, None)
    ref = tca.reference_contact(geom, "right")
    lo, hi = sweep.engagement_window(geom, "right", ref)
    pad = 0.01 * (hi - lo)
    grid = np.linspace(lo + pad, hi - pad, 50)
    try:
        for name, fn in saved.items():
            setattr(core, name, counted(name, fn))
        backends.namespace.cache_clear()
        sol = tca.solve_grid(geom, "right", errors, grid, solver=Solver("numpy"))
    finally:
        for name, fn in saved.items():
            setattr(core, name, fn)
        backends.namespace.cache_clear()
    points = sol.status.size
    return {name: tally[name] / points for name in COUNTED}, np.bincount(sol.status.ravel(), minlength=4) / points


def main():
    import argparse

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--crowned", type=float, metavar="UM", help="C_alpha = C_beta on both members (W3: 20)")
    ap.add_argument("--counts", type=int, metavar="SETS", help="also count calls per point (numpy backend)")
    ap.add_argument("--repeats", type=int, default=15, help="timed loops per piece; the best is kept (15)")
    a = ap.parse_args()
    numba.set_num_threads(1)
    if a.crowned:
        from beveloid.studies.crowning import crowned_geometry

        geom = crowned_geometry("case1", a.crowned)
    else:
        geom = Pair.from_spec(ROOT / "examples" / "case1.toml").geometry
    ref = tca.reference_contact(geom, "right")
    problem = geom.problem("right")
    e = np.zeros(5)
    x, phi = ref.x.copy(), ref.pinion_angle
    s = tca.evaluate(geom, "right", ref.x, ref.pinion_angle, e)
    F, J = np.array(s.residual), np.array(s.residual_D_unknowns)
    evals, candidates, solves, margins = _loops()
    rows = [
        ("contact system + Jacobians (1 evaluation)", _best(evals, (problem, x, phi, e), a.repeats)),
        ("edge candidate system (pinion form limit)", _best(candidates, (problem, 0, -1, x, phi, e), a.repeats)),
        ("corner candidate system (pinion form limit, gear form limit)",
         _best(candidates, (problem, 0, 4, x, phi, e), a.repeats)),
        ("5x5 solve (partial pivoting)", _best(solves, (J.copy(), F.copy()), a.repeats)),
        ("flank boundary check (margins of both members)", _best(margins, (problem, x.copy(), phi, e), a.repeats)),
    ]
    sweep.analyze(geom, sweep.Options(flank="right", samples=100, positions=50))
    r = sweep.analyze(geom, sweep.Options(flank="right", samples=10_000, positions=50))
    rows.append(("whole compiled path loop per point", r.seconds / r.contact_points_solved))
    rows.append(("whole sweep per point (window, stats)", r.seconds_total / r.contact_points_solved))
    for name, sec in rows:
        print(f"{name:<62} {sec * 1e6:6.3f} us")
    print(f"Newton iterations per point (mean, tangency and edge searches): {r.newton_iterations_mean:.3f}")
    if a.counts:
        per_point, mix = counts(geom, a.counts)
        print(f"\ncalls per point, numpy backend, {a.counts} error sets x 50 positions "
              f"(ok {mix[0]:.3f}, edge {mix[1]:.3f}, outside {mix[2]:.3f}, failed {mix[3]:.3f}):")
        for name, v in per_point.items():
            print(f"  {name:<24} {v:6.3f}")


if __name__ == "__main__":
    main()

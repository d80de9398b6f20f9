"""Where the compiled sweep's time goes: per-point cost of each piece, on one core.

    python benchmarks/profile_sweep.py
    python benchmarks/profile_sweep.py --crowned 20   # W3's pair: both members crowned by 20 um

Times, for the W2 workload's points (case 1, right flank): one evaluation of the composed
contact system (two surface jets + the Eq 38 assembly, with Jacobians), the 5x5 solve, the
flank-boundary check (margins from the surface points the evaluation left behind), and the
whole compiled path loop.  Not a test.
"""
import time
from pathlib import Path

import numba
import numpy as np

from beveloid import sweep, tca
from beveloid.design import design
from beveloid.solver import backends
from beveloid.spec import load_spec

ROOT = Path(__file__).resolve().parents[1]
CORE = backends.namespace("compiled")  # the solver core's own compiled functions


def main():
    import argparse

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--crowned", type=float, metavar="UM", help="C_alpha = C_beta on both members (W3: 20)")
    a = ap.parse_args()
    numba.set_num_threads(1)
    if a.crowned:
        from beveloid.crowning_study import crowned_geometry

        geom = crowned_geometry("case1", a.crowned)
    else:
        geom = tca.PairGeometry.from_design(design(load_spec(ROOT / "examples" / "case1.toml")))
    ref = tca.reference_contact(geom, "right")
    problem = geom.problem("right")
    e = np.zeros(5)
    n = 200_000
    core_evaluate, core_solve = CORE.evaluate, CORE.solve_linear  # dispatchers: numba globals
    ws_fn, margin_fn = CORE.workspace, CORE.contact_margin_point

    @numba.njit
    def evals(problem, x, phi, e, n):
        ws = ws_fn()
        F, J, Je, Jp = np.empty(5), np.empty((5, 5)), np.empty((5, 5)), np.empty(5)
        s = 0.0
        for i in range(n):
            core_evaluate(problem, x, phi + 1e-9 * i, e, ws, F, J, Je, Jp)
            s += F[0]
        return s

    @numba.njit
    def solves(J, F, n):
        out = np.empty(5)
        s = 0.0
        for _ in range(n):
            F[0] += 1e-12
            core_solve(J, F, out)
            s += out[0]
        return s

    @numba.njit
    def margins(problem, x, phi, e, b1, b2, n):
        ws = ws_fn()
        F, J, Je, Jp = np.empty(5), np.empty((5, 5)), np.empty((5, 5)), np.empty(5)
        core_evaluate(problem, x, phi, e, ws, F, J, Je, Jp)
        s = 0.0
        for _ in range(n):
            x[0] += 1e-12
            m, _ = margin_fn(x, b1, b2, ws)
            s += m
        return s

    s = tca.evaluate(geom, "right", ref.x, ref.pinion_angle, e)
    F, J = np.array(s.residual), np.array(s.residual_D_unknowns)
    b1, b2 = geom.pinion.blank(), geom.gear.blank()
    evals(problem, ref.x.copy(), ref.pinion_angle, e, 10)
    solves(J.copy(), F.copy(), 10)
    margins(problem, ref.x.copy(), ref.pinion_angle, e, b1, b2, 10)
    rows = []
    t = time.perf_counter(); evals(problem, ref.x.copy(), ref.pinion_angle, e, n); rows.append(("contact system + Jacobians (1 evaluation)", time.perf_counter() - t))  # noqa: E702
    t = time.perf_counter(); solves(J.copy(), F.copy(), n); rows.append(("5x5 solve (partial pivoting)", time.perf_counter() - t))  # noqa: E702
    t = time.perf_counter(); margins(problem, ref.x.copy(), ref.pinion_angle, e, b1, b2, n); rows.append(("flank boundary check (margins of both members)", time.perf_counter() - t))  # noqa: E702
    sweep.sweep(geom, "right", samples=100, positions=50)
    r = sweep.sweep(geom, "right", samples=10_000, positions=50)
    rows.append(("whole compiled path loop per point", r.seconds * n / r.contact_points_solved))
    rows.append(("whole sweep per point (window, stats)", r.seconds_total * n / r.contact_points_solved))
    for name, sec in rows:
        print(f"{name:<48} {sec / n * 1e6:6.3f} us/point")
    print(f"Newton iterations per point (mean): {r.newton_iterations_mean:.3f}; kernel evaluations per point: "
          f"{1 + r.newton_iterations_mean:.3f} plus the tangent solve")


if __name__ == "__main__":
    main()

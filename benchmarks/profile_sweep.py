"""Where the compiled sweep's time goes: per-point cost of each piece, on one core.

    python benchmarks/profile_sweep.py

Times, for the W2 workload's points (case 1, right flank): one evaluation of the generated
residual + Jacobians, the 5x5 solve, the flank-boundary check (two surface evaluations), and
the whole compiled path loop.  Not a test.
"""
import time
from pathlib import Path

import numba
import numpy as np

from beveloid import compiled, sweep, tca
from beveloid.design import design
from beveloid.spec import load_spec

ROOT = Path(__file__).resolve().parents[1]


@numba.njit(cache=True)
def _evals(x, phi, e, p, n):
    F = np.empty(5)
    J = np.empty((5, 5))
    Je = np.empty((5, 5))
    Jp = np.empty(5)
    s = 0.0
    for i in range(n):
        compiled._residual(1, x, phi + 1e-9 * i, e, p, F, J, Je, Jp)
        s += F[0]
    return s


@numba.njit(cache=True)
def _solves(J, F, n):
    out = np.empty(5)
    s = 0.0
    for i in range(n):
        F[0] += 1e-12
        compiled._solve(J, F, out)
        s += out[0]
    return s


@numba.njit(cache=True)
def _margins(x, p, lim, n):
    pt, nr, ph = np.empty(3), np.empty(3), np.empty(1)
    s = 0.0
    for i in range(n):
        x[0] += 1e-12
        s += compiled._margin(1, x, p, lim, pt, nr, ph)
    return s


def main():
    numba.set_num_threads(1)
    geom = tca.PairGeometry.from_design(design(load_spec(ROOT / "examples" / "case1.toml")))
    ref = tca.reference_contact(geom, "right")
    p = np.array(geom.kernel_params(), float)
    lim = tca._limits(geom)
    e = np.zeros(5)
    n = 500_000
    F, J, _, _ = tca.evaluate(geom, "right", ref.x, ref.pinion_angle, e)
    _evals(ref.x.copy(), ref.pinion_angle, e, p, 10)
    _solves(np.array(J), np.array(F), 10)
    _margins(ref.x.copy(), p, lim, 10)
    rows = []
    t = time.perf_counter(); _evals(ref.x.copy(), ref.pinion_angle, e, p, n); rows.append(("residual + Jacobians (1 evaluation)", time.perf_counter() - t))
    t = time.perf_counter(); _solves(np.array(J), np.array(F), n); rows.append(("5x5 solve (partial pivoting)", time.perf_counter() - t))
    t = time.perf_counter(); _margins(ref.x.copy(), p, lim, n); rows.append(("flank boundary check (2 surfaces)", time.perf_counter() - t))
    sweep.sweep(geom, "right", samples=100, positions=50)
    r = sweep.sweep(geom, "right", samples=10_000, positions=50)
    rows.append(("whole compiled path loop per point", r.seconds * n / r.contact_points_solved))
    rows.append(("whole sweep per point (window, stats)", r.seconds_total * n / r.contact_points_solved))
    for name, sec in rows:
        print(f"{name:<42} {sec / n * 1e6:6.3f} us/point")
    print(f"Newton iterations per point (mean): {r.newton_iterations_mean:.3f}; kernel evaluations per point: "
          f"{1 + r.newton_iterations_mean:.3f} plus the tangent solve")


if __name__ == "__main__":
    main()

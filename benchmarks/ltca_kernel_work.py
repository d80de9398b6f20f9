"""The contact solve's arithmetic in the tolerance box: factorizations and products counted, not timed.

    python benchmarks/ltca_kernel_work.py [--samples 16] [--torques-nm 100,200,400] [--every 8]

Not a test.  Runs docs/optimize.md's spec (case 1 tilted by vertical_deg = 0.05, FE tooth) through ``beveloid
ltca --samples`` once to warm up, then again with every call of the compiled contact solve
(``kernel.solve_positions``) recorded (its blocks with the rows it made and their tables, cells and start
sets; every ``--every``-th call kept; the rows it made counted over all calls), and solves the kept calls again with the same kernel run interpreted (the numpy backend's module),
its block solves and products counted: the factorizations (and their multiply-adds, m^3/6 + 2 m^2 for m
trial cells), the multiply-adds of the products C[:, S] p_S, the iterations and the trial-set sizes.  Counts
are exact and do not depend on the machine's load, unlike this host's timings (docs/performance.md, issue
59); each kept call's pressures are compared with the compiled kernel's.
"""
from __future__ import annotations

import argparse
import contextlib
import io
import os
import sys
import tempfile
from pathlib import Path

import numpy as np


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=16)
    ap.add_argument("--torques-nm", default="100,200,400")
    ap.add_argument("--every", type=int, default=8, help="keep every EVERY-th call of the contact solve")
    a = ap.parse_args()
    if a.every < 1:
        ap.error(f"--every {a.every}: must be an integer >= 1")

    from beveloid.cli import main as cli
    from beveloid.ltca.mechanics import kernel
    from beveloid.spec import example_text

    spec = Path(tempfile.mkdtemp()) / "case1_tilted.toml"
    spec.write_text(example_text("case1").replace("vertical_deg = 0.0 ", "vertical_deg = 0.05", 1))
    argv = ["ltca", str(spec), "--torque-nm", a.torques_nm, "--samples", str(a.samples), "--json"]
    quiet = lambda: contextlib.ExitStack() if os.environ.get("VERBOSE") else contextlib.redirect_stderr(io.StringIO())  # noqa: E731
    with contextlib.redirect_stdout(io.StringIO()), quiet():
        cli(argv)
    kept, seen, rows = [], [0], np.zeros(3)
    real = kernel.kernels

    class Recording:
        def __init__(self, k):
            self.k = k

        def __getattr__(self, name):
            return getattr(self.k, name)

        def solve_positions(self, layout, cells, limits, out):
            self.k.solve_positions(layout, cells, limits, out)
            r = layout.rows
            rows[:] += (r.built.sum(), r.loaded.sum() * r.built.shape[1], r.built.size)
            if seen[0] % a.every == 0:
                kept.append((kernel.Layout(*[np.array(x, copy=True) for x in layout[:-1]],
                                           kernel.Rows(*[np.array(x, copy=True) for x in layout.rows])),
                             kernel.Cells(*[np.array(x, copy=True) for x in cells]),
                             kernel.Start(limits.tolerance, limits.max_iterations, limits.starts.copy(),
                                          limits.given.copy()), out.pressure.copy()))
            seen[0] += 1

    kernel.kernels = lambda solver=None: Recording(real(solver))
    try:
        with contextlib.redirect_stdout(io.StringIO()), quiet():
            cli(argv)
    finally:
        kernel.kernels = real

    count = {"factorizations": 0, "factor_fma": 0.0, "product_fma": 0.0, "trial_cells": []}
    plain = sys.modules[kernel.__name__]  # the module itself: the kernel interpreted
    factor_solve, matvec = plain._factor_solve, plain._matvec

    def counted_factor_solve(blocks, o, s, m, sym, wk):
        count["factorizations"] += 1
        count["factor_fma"] += m ** 3 / 6 + 2 * m * m
        count["trial_cells"].append(m)
        return factor_solve(blocks, o, s, m, sym, wk)

    def counted_matvec(layout, j, active, p, out):
        start, size = layout.start, layout.size
        count["product_fma"] += sum(int(active[start[b]:start[b] + size[b]].sum()) * int(size[b])
                                    for b in range(size.size))
        return matvec(layout, j, active, p, out)

    plain._factor_solve, plain._matvec = counted_factor_solve, counted_matvec
    iterations, differ = [], 0.0
    try:
        for layout, cells, limits, pressure in kept:
            p, result = np.zeros_like(pressure), np.zeros((pressure.shape[0], 5))
            plain.solve_positions(layout, cells, limits, kernel.Output(p, result))
            iterations.extend(result[:, 1].tolist())
            differ = max(differ, float(np.abs(p - pressure).max() / max(np.abs(pressure).max(), 1e-300)))
    finally:
        plain._factor_solve, plain._matvec = factor_solve, matvec
    m = np.array(count["trial_cells"])
    its = np.array(iterations)
    print(f"beveloid {' '.join(argv[:1])} case1_tilted.toml {' '.join(argv[2:])}: {seen[0]} calls of the contact "
          f"solve, {len(kept)} kept (every {a.every}), {its.size} problems")
    print(f"  rows of the blocks made (kernel.Rows; all calls): {rows[0]:.0f} of the loaded pairs' {rows[1]:.0f} "
          f"({rows[0] / rows[1]:.3f}), of all {rows[2]:.0f} ({rows[0] / rows[2]:.3f})")
    print(f"  iterations a problem: mean {its.mean():.2f}; " + ", ".join(
        f"{k}: {int((its == k).sum())}" for k in range(1, int(its.max()) + 1)))
    print(f"  factorizations: {count['factorizations']} ({count['factorizations'] / its.size:.2f} a problem), "
          f"trial cells mean {m.mean():.1f}, median {np.median(m):.0f}, largest {m.max()}; "
          f"{count['factor_fma']:.3g} multiply-adds")
    print(f"  products C[:, S] p_S: {count['product_fma']:.3g} multiply-adds "
          f"(factorizations / products: {count['factor_fma'] / max(count['product_fma'], 1):.2f})")
    print(f"  pressures against the compiled kernel's: largest relative difference {differ:.1e}")


if __name__ == "__main__":
    main()

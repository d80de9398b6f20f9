"""How small must a Newton step be for the residual after it to be below the tolerance?

    python benchmarks/newton_final_step.py

The solver core ends Newton after a step s with FINAL_STEP_K |s|^2 <= tol without evaluating
again (beveloid/solver/newton.py).  This script measures, with that shortcut switched off, every
Newton step that was followed by convergence on W2-like paths (case 1, 20 error sets x 50
positions, right flank, numpy backend) for the involute pair and its crowned variant (20 um):
the residual before the step, the step size |s| (angle times the length scale) and the residual
after it, and K = residual after / |s|^2 for the steps above round-off.  Not a test.
"""
import numpy as np

from beveloid import sweep, tca
from beveloid.studies.crowning import crowned_geometry
from beveloid.design import design
from beveloid.solver import Solver, first_touch, newton
from beveloid.spec import load_example


def measure(geom):
    steps = []
    original = newton.newton_update

    def recording(F, J, x, step, r, tol, last, scale):
        s = original(F, J, x, step, r, tol, last, scale)
        size = max(max(abs(step[:4])), abs(step[4]) * scale) if s == 0 else 0.0
        steps.append((s, r, size))
        return s

    saved = newton.FINAL_STEP_K
    newton.FINAL_STEP_K = float("inf")  # no shortcut: every step is checked
    for mod in (newton, first_touch):  # the modules whose functions call newton_update
        mod.newton_update = recording
    try:
        lo, hi = sweep.engagement_window(geom, "right", solver=Solver("numpy"))
        steps.clear()
        tca.solve_grid(geom, "right", sweep.draw_errors(20, seed=0), np.linspace(lo, hi, 50), solver=Solver("numpy"))
    finally:
        newton.FINAL_STEP_K = saved
        for mod in (newton, first_touch):
            mod.newton_update = original
    rows = np.array([(a[1], a[2], b[1]) for a, b in zip(steps, steps[1:]) if a[0] == 0 and b[0] == 1])
    return rows, tca.newton_tolerance(geom)


def main():
    for name, geom in (("involute", tca.PairGeometry.from_design(design(load_example("case1")))),
                       ("crowned 20 um", crowned_geometry("case1", 20.0))):
        rows, tol = measure(geom)
        big = rows[rows[:, 1] > 1e-6]  # steps whose K|s|^2 is above round-off (~3e-14 mm)
        k = big[:, 2] / big[:, 1] ** 2
        print(f"{name}: {len(rows)} final Newton steps, tolerance {tol:.2e} mm")
        for q in (50, 90, 100):
            r0, s, r1 = np.percentile(rows, q, axis=0)
            print(f"  p{q:<3} residual before {r0:.2e} mm, step {s:.2e} mm, residual after {r1:.2e} mm")
        print(f"  K = after / step^2 over {len(big)} steps > 1e-6 mm: median {np.median(k):.3g}, "
              f"max {k.max():.3g} /mm (newton.FINAL_STEP_K = {newton.FINAL_STEP_K})")


if __name__ == "__main__":
    main()

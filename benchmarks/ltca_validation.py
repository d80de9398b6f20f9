"""The numbers of docs/validation.md section 7 (loaded contact): Hertz limit and the crossed pairs'
mesh stiffness with the plate tooth; patch length and moment residual with the default (FE) tooth.
Not a test (the tests assert the Hertz limit and the moment balance).

    python benchmarks/ltca_validation.py        # ~1 min on the 2-core machine
"""
import math

import numpy as np

from beveloid import ltca, tca
from beveloid.design import design
from beveloid.ltca.mechanics import hertz
from beveloid.spec import load_example

g1 = tca.PairGeometry.from_design(design(load_example("case1")))
# (1) Hertz
print("HERTZ (reference: curvature.relative_curvature at the tangency; 'fit' = the gap's own quadratic form)")
from beveloid import curvature


def module3_variant():
    """Case 1 scaled to module 3 (z 21/33, offset 83.55 mm, faces 25/30 mm; not a shipped example)."""
    import tomllib

    from beveloid.pair import Pair
    from beveloid.spec.parse import example_text

    spec = tomllib.loads(example_text("case1"))
    spec["pair"].update(normal_module_mm=3.0, offset_mm=83.55)
    spec["pinion"].update(teeth=21, face_width_mm=25.0)
    spec["gear"].update(teeth=33, face_width_mm=30.0)
    return Pair.from_spec(spec).geometry


for case, flank, T in (("case1", "left", 1.0), ("case1", "left", 2.0), ("case1", "left", 5.0), ("case1", "left", 20.0),
                       ("case2", "left", 2.0), ("case1", "right", 1.0), ("case2", "right", 1.0),
                       ("module3", "left", 1.0), ("module3", "right", 1.0)):
    g = module3_variant() if case == "module3" else tca.PairGeometry.from_design(design(load_example(case)))
    r = ltca.analyze(g, ltca.LoadCase(T), ltca.Options(flank=flank, positions=3, pairs=1, tooth_model="plate"))  # the default grid
    nx, ny = r.grid.across_cells, r.grid.along_cells
    j, k = 1, 0
    p = r.pressure_mpa[j, k].reshape(nx, ny); h = r.gap.gap_mm[j, k].reshape(nx, ny); inside = r.gap.in_flank[j, k].reshape(nx, ny)
    x, y = r.cell_coordinates_mm(j, k)
    w = p/p.sum(); mx, my = (w*x).sum(), (w*y).sum()
    a_ = math.sqrt(5*(w*(x-mx)**2).sum()); b_ = math.sqrt(5*(w*(y-my)**2).sum())
    fit = inside & (h <= np.percentile(h[inside], 60))
    m = np.stack([x[fit]**2, x[fit]*y[fit], y[fit]**2, x[fit], y[fit], np.ones(fit.sum())], -1)
    c = np.linalg.lstsq(m, h[fit], rcond=None)[0]
    fA, fB = np.linalg.eigvalsh(np.array([[c[0], c[1]/2], [c[1]/2, c[2]]]))
    rc = curvature.relative_curvature(g, flank, r.tangency_unknowns[j, k], r.pair_pinion_angle[j, k], np.zeros(5))
    A, B = np.linalg.eigvalsh(rc.H) / 2
    ref = hertz.hertz_point_contact(A, B, float(r.pair_load_n[j, k]), ltca.Material().e_star_mpa)
    print(f"{case} {flank} T={T} F={r.pair_load_n[j,k]:.1f}N R={1/(2*A):.0f}/{1/(2*B):.2f} (fit {1/(2*fA):.0f}/{1/(2*fB):.2f}) b={a_:.4f}/{ref.semi_minor_mm:.4f} ({a_/ref.semi_minor_mm-1:+.2%})  a={b_:.3f}/{ref.semi_major_mm:.3f} ({b_/ref.semi_major_mm-1:+.2%})  p={p.max():.1f}/{ref.max_pressure_mpa:.1f} ({p.max()/ref.max_pressure_mpa-1:+.2%})")
# (2) convergence: benchmarks/ltca_grid_convergence.py
# (4) stiffness
print("STIFFNESS")
for case in ("case1", "case2"):
    g = tca.PairGeometry.from_design(design(load_example(case)))
    res = {T: ltca.analyze(g, ltca.LoadCase(T), ltca.Options(flank="right", positions=9, pairs=3, tooth_model="plate")) for T in (400.0, 600.0)}
    r = res[600.0]
    inside = r.gap.in_flank
    r1 = np.median(r.gap.pinion_arm_mm[inside]); r2 = np.median(r.gap.gear_closure_mm[inside])
    dF = (600e3 - 400e3)/r1
    dd = (res[600.0].loaded_te - res[400.0].loaded_te) * r2 * 1e3  # um
    b = min(g.pinion.face_width_mm, g.gear.face_width_mm)
    c = dF/(dd*b)
    print(case, f"r1 {r1:.2f} r2 {r2:.2f} dF {dF:.0f} N  dd mean {dd.mean():.3f} um  c_gamma mean {c.mean():.2f} min {c.min():.2f} max {c.max():.2f} N/(mm um); b={b}")
print("PATCH LENGTH")
for case in ("case1", "case2"):
    g = tca.PairGeometry.from_design(design(load_example(case)))
    for T in (5.0, 200.0, 600.0):
        r = ltca.analyze(g, ltca.LoadCase(T), ltca.Options(flank="right", positions=9, pairs=3))  # the default (FE) tooth
        nx, ny = r.grid.across_cells, r.grid.along_cells
        j = 4; k = int(np.argmax(r.pair_load_n[j]))
        p = r.pressure_mpa[j, k].reshape(nx, ny) > 0
        cols = np.nonzero(p.any(axis=0))[0]
        dy = 2 * r.grid.along_half_mm[j, k] / ny
        length = (cols.max() - cols.min() + 1) * dy
        width = p.sum(axis=0).max() * 2 * r.grid.across_half_mm[j, k] / nx
        inside = r.gap.in_flank[j, k].reshape(nx, ny)
        mres = np.nanmax(np.abs(r.pinion_moment_nmm / (T * 1e3) - 1))
        print(case, T, f"pair {r.tooth_pairs[k]} length {length:.1f} mm width {width:.3f} mm ratio {length/width:.0f}  moment res {mres:.1e}  loads {np.round(r.pair_load_n[j])}")

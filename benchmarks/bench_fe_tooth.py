"""The FE tooth (issue 31): its cost, its convergence under --fe-refinement, and FE against plate.

    python -m benchmarks.bench_fe_tooth cost [--member gear]  # FE data of case 1's pinion (or gear), fresh
    python -m benchmarks.bench_fe_tooth solvers               # PARDISO vs SuperLU on that stiffness
    python -m benchmarks.bench_fe_tooth refinement            # PARDISO's solves with and without iterative refinement
    python -m benchmarks.bench_fe_tooth convergence [1 2 3]   # case 1 LTCA at each refinement (1.5: sizes / 1.5)
    python -m benchmarks.bench_fe_tooth compare               # FE vs plate, case 1 and case 2
    python -m benchmarks.bench_fe_tooth startup               # cached FE start-up vs the plate
    python -m benchmarks.bench_fe_tooth meshes [1 2 3]        # case 1 pinion mesh sizes
    python -m benchmarks.bench_fe_tooth sizes [1 2 3]         # element sizes and rho_F of case 1 and case 2 (no meshing)
    python -m benchmarks.bench_fe_tooth locate                # how far the load / reading points lie outside the mesh

Not a test.  ``cost`` and ``convergence`` compute the FE data into a fresh cache folder of their own
(removed at the end); ``compare`` and ``startup`` use the user cache (computed once, then cached).
Torque 500 N m on the pinion, right flank, 20 positions, 3 pairs (the LTCA defaults).
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time

import numpy as np

TORQUE_NM = 500.0


def _pair(case):
    from beveloid.pair import Pair

    return Pair.example(case)


def cost(member="pinion", case="case1", refinement=1):
    from beveloid.fe.tooth import tooth_data
    from beveloid.ltca import Material

    pair = _pair(case)
    m = Material.from_spec(pair.spec)
    e_mpa, nu = (m.pinion_e_mpa, m.pinion_nu) if member == "pinion" else (m.gear_e_mpa, m.gear_nu)
    t, cpu = time.perf_counter(), time.process_time()
    d = tooth_data(pair, member, e_mpa, nu, refinement, progress=lambda *s: print(s[-1], file=sys.stderr))
    out = {name: d.stat(name) for name in d.STATS}
    out["total_s"] = time.perf_counter() - t
    out["cpu_s"] = time.process_time() - cpu  # all threads' CPU time: the machine is shared
    out["load_average_1min"] = os.getloadavg()[0]
    out["dofs"] = out["free_dofs"]
    out["load_cases"] = int(d.compliance_mm_per_n.shape[0] * d.compliance_mm_per_n.shape[1])
    return out


def _factorisers():
    import scipy.sparse.linalg

    def pardiso(K):
        from beveloid.fe.solve import PardisoFactor

        return PardisoFactor(K)

    def cholespy(K):
        from cholespy import CholeskySolverD, MatrixType

        c = K.tocoo()
        f = CholeskySolverD(K.shape[0], c.row.astype(np.int32), c.col.astype(np.int32), c.data, MatrixType.COO)

        class Solved:
            def solve(self, rhs):
                x = np.zeros_like(rhs)
                f.solve(np.ascontiguousarray(rhs), x)
                return x
        return Solved()

    def splu(K):
        return scipy.sparse.linalg.splu(K.tocsc(), permc_spec="MMD_AT_PLUS_A")

    return {"pardiso": pardiso, "cholespy": cholespy, "splu": splu}


def solvers():
    """Each sparse factorisation on the case 1 pinion's clamped stiffness, 126 right-hand sides: on the
    mesh coarsened 2x (all three) and on the default mesh (SuperLU left out: it had not factorised
    it after 10 minutes)."""
    from beveloid.fe import solve
    from beveloid.fe.mesh import sector_mesh

    out = {}
    for coarsen, names in ((2.0, ("pardiso", "cholespy", "splu")), (1.0, ("pardiso", "cholespy"))):
        mesh = sector_mesh(_pair("case1"), "pinion", coarsen=coarsen)
        K = solve.stiffness(mesh, 2.06e5, 0.3)
        nd = 3 * np.arange(len(mesh.nodes))[:, None] + np.arange(3)
        fixed = np.unique(np.concatenate([nd[mesh.node_sets[n]].ravel() for n in solve.CLAMPED]))
        free = np.setdiff1d(np.arange(K.shape[0]), fixed)
        Kf = K[free][:, free]
        rhs = np.random.default_rng(0).standard_normal((Kf.shape[0], 126))
        row = {"dofs": int(Kf.shape[0]), "nnz": int(Kf.nnz)}
        for name in names:
            t0 = time.perf_counter()
            try:
                f = _factorisers()[name](Kf)
            except ImportError:
                row[name] = "not installed"
                continue
            t1 = time.perf_counter()
            x = f.solve(rhs)
            t2 = time.perf_counter()
            row[name] = {"factor_s": t1 - t0, "solve_126_s": t2 - t1,
                         "residual": float(np.abs(Kf @ x - rhs).max() / np.abs(rhs).max())}
            print(coarsen, name, row[name], file=sys.stderr, flush=True)
        out[f"coarsen_{coarsen:g}"] = row
    out["load_average_1min"] = os.getloadavg()[0]
    return out


def refinement():
    """PARDISO's solves of the case 1 pinion's right-flank load cases (the FE tooth's own loads, one
    factorisation) with MKL's default iterative refinement (up to 2 steps) and without it (what
    beveloid.fe.solve.PardisoFactor does): CPU seconds, the steps taken, the largest change of a
    displacement (relative to the largest) and the residuals max|K x - b| / max|b|."""
    import scipy.sparse

    from beveloid.fe import solve, tooth
    from beveloid.fe.mesh import sector_mesh
    from beveloid.ltca import Material
    from beveloid.tooth.body import body_pair

    pair = body_pair(_pair("case1"), "pinion")
    m = Material.from_spec(_pair("case1").spec)
    mesh = sector_mesh(pair, "pinion")
    elastic = solve.factorise(mesh, m.pinion_e_mpa, m.pinion_nu, solver="pardiso")
    g = tooth.load_grid(tooth.ToothSampler(pair.geometry, "pinion"), pair.geometry.normal_module_mm)
    pts, nrm = g.points_mm[1].reshape(-1, 3), g.normals[1].reshape(-1, 3)
    rhs = np.ascontiguousarray(solve.displacement_operator(elastic, solve.locate(mesh, pts), -nrm).T.toarray()[elastic.free])
    factor = elastic.lu
    K = factor.matrix + scipy.sparse.triu(factor.matrix, 1).T
    out = {"free_dofs": int(rhs.shape[0]), "load_cases": int(rhs.shape[1])}
    x = {}
    for steps in (2, 0):
        factor.solver.iparm[7] = steps
        cpu = time.process_time()
        x[steps] = factor.solve(rhs)
        out[f"max_steps_{steps}"] = {"cpu_s": time.process_time() - cpu, "steps_taken": int(factor.solver.iparm[6]),
                                     "residual": float(np.abs(K @ x[steps] - rhs).max() / np.abs(rhs).max())}
    out["max_change_relative"] = float(np.abs(x[0] - x[2]).max() / np.abs(x[2]).max())
    out["load_average_1min"] = os.getloadavg()[0]
    return out


def _summary(r, geom):
    ok = r.converged
    te = (r.loaded_te - r.unloaded_te)[ok] * 1e6
    share = r.pair_load_n[ok] / r.pair_load_n[ok].sum(axis=1, keepdims=True)
    out = {"loaded_te_mean_urad": float(np.mean(te)), "loaded_te_ptp_urad": float(np.ptp(r.loaded_te[ok]) * 1e6),
           "mesh_stiffness_mean_n_per_um": float(np.nanmean(r.mesh_stiffness_n_per_um[ok])),
           "max_pair_share": float(np.max(share)), "peak_pressure_mpa": float(np.nanmax(r.pair_surface_max_pressure_mpa)),
           "converged": int(ok.sum())}
    for m, v in r.root_stress_max_mpa().items():
        out[f"root_stress_max_{m}_mpa"] = v
    for m, where in r.root_stress_location().items():  # where the largest one sits: face z, height above the root cone
        if where is not None:
            out[f"root_stress_max_{m}_where_mm"] = [where["z_mm"], where["height_mm"]]
    # the surface peak against Hertz for pairs clear of the flank edges whose patch is long against the
    # tooth height (a / h > 0.5: where the plate departed from Hertz by 6-10 %, docs/loaded_contact.md 5.1)
    h = min(g.tip_height_mm + g.cutter_addendum_mm for g in (geom.pinion, geom.gear))
    a = r.patch_semi_axes_mm()[..., 1]
    ratio = r.pair_surface_max_pressure_mpa / r.pair_hertz_max_pressure_mpa
    long = np.isfinite(ratio) & np.isnan(r.pair_edge_max_pressure_mpa) & (a / h > 0.5)
    short = np.isfinite(ratio) & np.isnan(r.pair_edge_max_pressure_mpa) & (a / h <= 0.5)
    out["hertz_ratio_long_patch"] = [float(np.min(ratio[long])), float(np.max(ratio[long]))] if long.any() else None
    out["hertz_ratio_short_patch"] = [float(np.min(ratio[short])), float(np.max(ratio[short]))] if short.any() else None
    out["long_patches"] = int(long.sum())
    return out


def fe_options(refinement=1, **options):
    """``ltca.Options(**options)`` with the FE tooth's every element size divided by ``refinement``: an integer
    is ``fe_refinement``; a fraction (1.5) is every size times 1 / refinement through ``fe_coarsen``, which the
    users' option keeps at 1-8 and the mesh takes from 0.25 (a level between the default and refinement 2, whose
    FE data fit this machine where refinement 2's do not)."""
    from beveloid import ltca

    if float(refinement).is_integer():
        return ltca.Options(fe_refinement=int(refinement), **options)
    coarsen = options.pop("fe_coarsen", 1.0) / refinement
    out = ltca.Options(**options)
    object.__setattr__(out, "fe_coarsen", coarsen)
    return out


def _ltca(case, model, refinement=1):
    from beveloid import ltca

    t = time.perf_counter()
    pair = _pair(case)
    r = ltca.analyze(pair, ltca.LoadCase(TORQUE_NM), fe_options(refinement, tooth_model=model))
    out = _summary(r, pair.geometry)
    out["seconds"] = time.perf_counter() - t
    return out


def convergence(refinements):
    out = {}
    for n in refinements:
        out[n] = _ltca("case1", "fe", n)
        print(n, out[n], file=sys.stderr, flush=True)
    return out


def compare():
    out = {}
    for case in ("case1", "case2"):
        for model in ("plate", "fe"):
            out[f"{case}_{model}"] = _ltca(case, model)
            print(case, model, out[f"{case}_{model}"], file=sys.stderr, flush=True)
    return out


def meshes(refinements):
    """The case 1 pinion's sector mesh at each refinement: nodes, tets, free dofs, seconds, and the tets
    that keep straight edges (`fe.solve.element_geometry`: their curved map would fold or nearly) and
    of those the ones whose curved map folds (det J <= 0 at a quadrature point or a corner)."""
    from beveloid.fe import solve
    from beveloid.fe.mesh import sector_mesh

    out = {}
    for n in refinements:
        t = time.perf_counter()
        mesh = sector_mesh(_pair("case1"), "pinion", refinement=n)
        clamped = np.unique(np.concatenate([mesh.node_sets[c] for c in solve.CLAMPED]))
        curved = mesh.nodes[mesh.tets]
        kept = solve.element_geometry(curved)
        straightened = (kept != curved).any(axis=(1, 2))
        pts = np.vstack([solve.QUADRATURE, np.eye(4)])
        folded = np.min([solve.iso_gradients(curved, np.broadcast_to(q, (len(curved), 4)))[1] for q in pts], axis=0) <= 0
        out[n] = {"nodes": int(len(mesh.nodes)), "tets": int(len(mesh.tets)),
                  "free_dofs": int(3 * (len(mesh.nodes) - clamped.size)), "seconds": time.perf_counter() - t,
                  "straight_edged_tets": int(straightened.sum()), "folded_tets": int(folded.sum())}
        print(n, out[n], file=sys.stderr, flush=True)
    return out


def sizes(refinements):
    """Each member's element sizes (mm) at each refinement and its fillet's smallest radius of
    curvature rho_F at mid-face (`fe.mesh.mesh_sizes`, the rules of docs/loaded_contact.md 9.1)."""
    from beveloid.fe.mesh import mesh_sizes
    from beveloid.tooth.sampling import ToothSampler

    out = {}
    for case in ("case1", "case2"):
        geometry = _pair(case).geometry
        for member in ("pinion", "gear"):
            sampler = ToothSampler(geometry, member)
            out[f"{case} {member}"] = {n: {k: round(float(v), 4) for k, v in
                                           vars(mesh_sizes(sampler, geometry.normal_module_mm, n)).items()}
                                       for n in refinements}
    return out


#: a design whose pinion's flank elements are longer than its tooth is high at --fe-coarsen 8 (21 teeth,
#: 100 mm face, rack tip round 0.38 m_n): where the mesh's flank departs most from the flank
WIDE_PINION = {"pair": {"normal_module_mm": 5.0, "normal_pressure_angle_deg": 20.0, "shaft_angle_deg": 13.0,
                        "offset_mm": 209.751},
               "pinion": {"teeth": 21, "cone_angle_deg": 1.0, "helix_angle_deg": 15.0, "profile_shift": 0.2,
                          "face_width_mm": 100.0, "cutter_tip_radius_coefficient": 0.38},
               "gear": {"teeth": 60, "cone_angle_deg": 0.5, "face_width_mm": 110.0, "cutter_tip_radius_coefficient": 0.38}}


def _outside(values) -> dict:
    v = np.asarray(values, dtype=float).ravel()
    return {"max": float(v.max()), "p95": float(np.percentile(v, 95)), "median": float(np.median(v)),
            "outside": int(np.count_nonzero(v))}


def locate():
    """How far the FE tooth's load points, its reading points and the points read along the normal
    (x - d n, the reading before the feet of beveloid.fe.tooth.reading_feet) lie from where the mesh
    reads them (beveloid.fe.solve.locate's outside_mm, mm), per member: case 1 and case 2 at the
    default mesh and the suite's coarse one (x 3), and WIDE_PINION at x 8 (the pinion)."""
    from beveloid.fe import solve, tooth
    from beveloid.fe.mesh import sector_mesh
    from beveloid.pair import Pair
    from beveloid.tooth.body import body_pair
    from beveloid.tooth.sampling import ToothSampler

    runs = [(case, member, coarsen) for coarsen in (1.0, 3.0) for case in ("case1", "case2") for member in ("pinion", "gear")]
    out = {}
    for case, member, coarsen in runs + [("wide_pinion", "pinion", 8.0)]:
        pair = body_pair(Pair.from_spec(WIDE_PINION) if case == "wide_pinion" else _pair(case), member)
        mesh = sector_mesh(pair, member, coarsen=coarsen)
        g = tooth.load_grid(ToothSampler(pair.geometry, member), pair.geometry.normal_module_mm)
        d = g.depth_mm[..., None]
        where = {"load": g.points_mm, "reading": tooth.reading_points(g.feet_mm, g.feet_normals, d),
                 "along_normal": g.points_mm - d * g.normals}
        row = {"flank_element_mm": mesh.sizes.flank_mm, "tets": int(len(mesh.tets))}
        for name, pts in where.items():
            row[name] = _outside(solve.locate(mesh, pts.reshape(-1, 3)).outside_mm)
        row["load_max_per_flank_element"] = row["load"]["max"] / mesh.sizes.flank_mm
        row["foot_moved_max_mm"] = float(np.max(np.linalg.norm(g.feet_mm - g.points_mm, axis=-1)))
        out[f"{case}_{member}_x{coarsen:g}"] = row
        print(case, member, coarsen, row, file=sys.stderr, flush=True)
    return out


def startup():
    """Seconds to the first position: Options + teeth (cached FE data read) for each model."""
    from beveloid import ltca
    from beveloid.ltca.model.teeth import member_teeth

    pair = _pair("case1")
    mat = ltca.Material.from_spec(pair.spec)
    out = {}
    for i, model in enumerate(("fe", "plate", "fe", "plate")):
        t = time.perf_counter()
        member_teeth(pair, pair.geometry, ltca.Options(tooth_model=model), mat)[0]
        out[f"{model}_call{i // 2 + 1}_s"] = time.perf_counter() - t  # call 1 includes the imports
    out["load_average_1min"] = os.getloadavg()[0]
    return out


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("what", choices=("cost", "solvers", "refinement", "convergence", "compare", "startup", "meshes",
                                     "sizes", "locate"))
    p.add_argument("refinements", nargs="*", type=float, default=[1, 2, 3],
                   help="FE refinements (integers, or a fraction such as 1.5: every size / 1.5)")
    p.add_argument("--member", choices=("pinion", "gear"), default="pinion", help="cost: the member (default pinion)")
    p.add_argument("--case", choices=("case1", "case2"), default="case1", help="cost: the design (default case1)")
    a = p.parse_args(argv)
    if a.what == "refinement":  # MKL on one thread, as on `beveloid paper`'s worker processes (read as MKL loads)
        os.environ["MKL_NUM_THREADS"] = "1"
    fresh = tempfile.TemporaryDirectory(prefix="beveloid-fe-bench-") if a.what in ("cost", "convergence") else None
    if fresh is not None:
        os.environ["BEVELOID_CACHE_DIR"] = fresh.name
    a.refinements = [int(n) if float(n).is_integer() else n for n in a.refinements]
    fn = {"cost": lambda: cost(a.member, a.case, (a.refinements or [1])[0]), "solvers": solvers, "refinement": refinement, "compare": compare, "startup": startup,
          "convergence": lambda: convergence(a.refinements), "meshes": lambda: meshes(a.refinements),
          "sizes": lambda: sizes(a.refinements),
          "locate": locate}[a.what]
    try:
        print(json.dumps(fn(), indent=1))
    finally:
        if fresh is not None:
            fresh.cleanup()


if __name__ == "__main__":
    main()

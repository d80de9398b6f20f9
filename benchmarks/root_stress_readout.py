"""Which smoothed read-out of the FE tooth's fillet stresses reads the same on the default mesh and on
refinement 2?  (issue 57.5; docs/validation.md 10.2)

Before FE_DATA_VERSION 4 the LTCA's, the rating's and optimize's root stress was the largest principal stress
of the FE tooth's fillet nodes' tensors smoothed by a local least-squares fit (:func:`smoothing_matrix`, kept
here): along the face +-0.15 m_n, in height above the root cone +-0.15 of the fillet element at refinement 1,
linear in both; today's is the read-out on a grid fixed by the geometry (``fe.contact.readout_matrix``,
``benchmarks/rating_root_convergence.py --jitter`` measures it).  Candidates for that nodal fit, each measured on the same loads: the default's LTCA at the rating's torque and default positions
(the load redistribution between meshes is at most 0.5 %: ``benchmarks/rating_root_convergence.py``), read
by the FE tooth at refinement 1 (the default) and at refinement 2 with its nodal means
(``tooth_data(..., smooth=False)``) smoothed by the candidate.  A candidate is a window across the fillet,
in one of two coordinates, and a fit across it that is linear or quadratic (always linear along the face):

* ``height``: the height above the root cone, today's coordinate.  The fillet's node rows (the mesh is
  lofted through sections: its nodes lie in rows along the face) crowd in height where the fillet turns
  into the root (h ~ u^2 / 2 rho), where the largest stress sits;
* ``profile``: the distance u along the section's fillet profile from the root cone
  (:func:`fillet_profile_mm`), in which the rows lie evenly, at most half a fillet element apart (P2).

Widths in fillet elements at refinement 1 (the same physical window on both meshes), or, marked
``per mesh``, in the mesh's own fillet elements (the same number of rows on both).  Prints a markdown
table: per member the default / refinement 2 - 1 of each candidate.

    python benchmarks/root_stress_readout.py [--designs case1,case2,R1,R2,R3]   # one design per process; or a .toml path or R5701-k
    python benchmarks/root_stress_readout.py --notch [--refinement 1 2]   # against the 2D notch benchmark

``--notch``: the candidates on the near-spur pinions of ``benchmarks/notch_benchmark.py fe-tooth`` (a line
load uniform along the face at the tip and at d_en) over the converged 2D section (refinement 4).
Peak memory: 9-13 GB a design measured while the script held every candidate's copy at once (it now holds
one); FE data cached (BEVELOID_CACHE_DIR).
"""
from __future__ import annotations

import argparse
import dataclasses
import itertools
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import numpy as np  # noqa: E402

#: (coordinate, half-width in fillet elements, fit order across the fillet, per mesh)
CANDIDATES = (("height", 0.15, 1, False), ("height", 0.5, 1, False), ("height", 0.5, 2, False),
              ("profile", 0.5, 2, False), ("profile", 0.75, 2, False), ("profile", 1.0, 2, False),
              ("profile", 0.75, 2, True), ("profile", 1.0, 2, True))
#: the fillet profile's tables (fillet_profile_mm): sections along the face, points along each profile
PROFILE_SECTIONS = 17
PROFILE_POINTS = 257


def label(c) -> str:
    coord, width, order, per_mesh = c
    return f"{coord} ±{width:g} h{' per mesh' if per_mesh else ''}, {('linear', 'quadratic')[order - 1]}"


def fillet_profile_mm(sampler, flank: str, points_mm, height_mm) -> np.ndarray:
    """(n,) each of the ``flank`` fillet's nodes' (``points_mm`` (n, 3), ``height_mm`` (n,) above the root
    cone) distance along its section's fillet profile from the root cone (``fillet_points`` s = 0), read
    from its height through tables of :data:`PROFILE_SECTIONS` sections (the height rises along each
    profile), linear between sections; a node below the profile's foot (root land meshed with a short
    fillet) or above its top carries its height's distance from there."""
    z0, z1 = sampler.z_range_mm
    zt = np.linspace(z0, z1, PROFILE_SECTIONS)
    prof = sampler.fillet_points(flank, np.linspace(0.0, 1.0, PROFILE_POINTS), zt)  # (n_s, n_z, 3)
    h = np.maximum.accumulate(np.hypot(prof[..., 0], prof[..., 1]) - sampler.root_radius_mm(zt)[None], axis=0)
    arc = np.concatenate([np.zeros((1, len(zt))), np.cumsum(np.linalg.norm(np.diff(prof, axis=0), axis=-1), axis=0)])
    p, hh = np.asarray(points_mm, dtype=float), np.asarray(height_mm, dtype=float)
    at = np.stack([np.interp(hh, h[:, k], arc[:, k]) + np.minimum(hh - h[0, k], 0.0) + np.maximum(hh - h[-1, k], 0.0)
                   for k in range(len(zt))])  # (n_z, n)
    f = np.interp(p[:, 2], zt, np.arange(len(zt)))
    k = np.minimum(f.astype(int), len(zt) - 2)
    t = f - k
    cols = np.arange(len(hh))
    return (1.0 - t) * at[k, cols] + t * at[k + 1, cols]


#: a node with fewer neighbours in its window than this keeps its own stress
_MIN_NODES = 4


def smoothing_matrix(points_mm, height_mm, face_mm: float, height_band_mm: float, height_order: int = 1):
    """(nf, nf) scipy CSR: row i the weights of a local linear least-squares fit, s(z, h) = c0 + c1 dz + c2 dh
    over the fillet nodes j within |z_j - z_i| <= ``face_mm`` and |h_j - h_i| <= ``height_band_mm`` (h the
    height above the root cone), evaluated at node i (c0).  Linear in the nodes' stresses, so that the
    smoothed tensors of a load set are the smoothed sum of its columns' (fe.principal's bounds hold), and
    exact for a stress that varies linearly along the face and in height.  ``height_order`` 2 adds c3 dh^2:
    exact for a stress quadratic across the fillet, a curved peak's top not read as its window's mean
    (it needs nodes at three heights in a window).  Padding repeats of the last
    node (``ToothData.fillet_points_mm``) take the last node's row; a node with fewer than
    :data:`_MIN_NODES` in its window keeps its own value."""
    import scipy.sparse
    from scipy.spatial import cKDTree

    if height_order not in (1, 2):
        raise ValueError(f"height_order = {height_order!r}: must be 1 (linear across the fillet) or 2 (quadratic)")
    p = np.asarray(points_mm, dtype=float)
    h = np.asarray(height_mm, dtype=float)
    nf = len(p)
    n = nf
    while n > 1 and np.array_equal(p[n - 2], p[-1]) and h[n - 2] == h[-1]:
        n -= 1
    x = np.stack([p[:n, 2] / face_mm, h[:n] / height_band_mm], axis=1)
    pairs = cKDTree(x).query_pairs(r=1.0, p=np.inf, output_type="ndarray")
    i = np.concatenate([np.arange(n), pairs[:, 0], pairs[:, 1]])  # each node with itself and its neighbours
    j = np.concatenate([np.arange(n), pairs[:, 1], pairs[:, 0]])
    d = x[j] - x[i]
    a = np.column_stack([np.ones(len(i)), d] + ([d[:, 1] ** 2] if height_order == 2 else []))
    k = a.shape[1]
    normal = np.zeros((n, k, k))
    np.add.at(normal, i, a[:, :, None] * a[:, None, :])
    # the fit's value at the node: row 0 of pinv(A) = (A^T A)^+ A^T, rank-deficient windows included
    w = np.einsum("pk,pk->p", np.linalg.pinv(normal, rcond=1e-12)[i, 0], a)
    alone = np.bincount(i, minlength=n) < _MIN_NODES
    keep = ~alone[i]
    rows = [i[keep], np.flatnonzero(alone), np.arange(n, nf)]
    cols = [j[keep], np.flatnonzero(alone), np.full(nf - n, n - 1)]
    vals = [w[keep], np.ones(int(alone.sum())), np.ones(nf - n)]
    return scipy.sparse.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                                   shape=(nf, nf))


def smooth_stress(stress, fillet_points_mm, fillet_height_mm, face_mm: float, height_band_mm: float,
                  height_order: int = 1) -> None:
    """Smooth ``stress`` (2 flanks loaded, 2 fillets, nf, 6, G; MPa per N) in place: every fillet node's
    tensor per load-grid node replaced by its local fit (:func:`smoothing_matrix`, ``height_order`` its
    order across the fillet), one (flank, fillet) slice at a time (no second copy of the whole operator)."""
    nf = stress.shape[2]
    for side in range(2):
        w = smoothing_matrix(fillet_points_mm[side], fillet_height_mm[side], face_mm, height_band_mm, height_order)
        for f in range(2):
            stress[f, side] = (w @ stress[f, side].reshape(nf, -1)).reshape(stress.shape[2:])


def smoothed_data(data, face_mm: float, height_band_mm: float, height_order: int = 1):
    """``data`` (a ToothData, unsmoothed: ``tooth_data(..., smooth=False)``) with every fillet node's stress
    tensor (per unit load on each load-grid node) replaced by its local fit over the window
    (:func:`smoothing_matrix`), and the window in ``smoothing_mm``.  Each node's stress is the mean of its
    tets' P2 stresses at the node and scatters from node to node by a few percent on an unstructured mesh;
    the largest of thousands of nodes sits on that scatter (docs/validation.md 12.2).  The window is narrow
    in height (the notch's peak at the bottom of the fillet is kept) and short along the face against the
    root stress of a contact patch (several mm wide).  :func:`beveloid.fe.tooth.tooth_data` returns its
    data smoothed this way."""
    import dataclasses

    if np.any(np.asarray(data.smoothing_mm) != 0.0):
        raise ValueError(f"smoothing_mm = {list(np.asarray(data.smoothing_mm))}: the data is already smoothed")
    st = np.array(data.stress_mpa_per_n, dtype=float)
    smooth_stress(st, data.fillet_points_mm, data.fillet_height_mm, face_mm, height_band_mm, height_order)
    return dataclasses.replace(data, stress_mpa_per_n=st, smoothing_mm=np.array([face_mm, height_band_mm], dtype=float))


def readouts(raw, sampler, face_mm: float, fillet_mm: float, refinement: int):
    """(candidate, ToothData) the nodal means ``raw`` smoothed by each candidate in turn (one copy of the
    stresses at a time); ``fillet_mm`` the fillet element at refinement 1."""
    from beveloid.names import FLANKS

    u = np.stack([fillet_profile_mm(sampler, f, raw.fillet_points_mm[i], raw.fillet_height_mm[i])
                  for i, f in enumerate(FLANKS)])
    across = {"height": raw, "profile": dataclasses.replace(raw, fillet_height_mm=u)}
    for c in CANDIDATES:
        yield c, smoothed_data(across[c[0]], face_mm, c[1] * fillet_mm / (refinement if c[3] else 1), c[2])


def designs(args) -> None:
    from rating_invariance import _torques
    from rating_root_convergence import _pair

    from beveloid import ltca
    from beveloid.fe.cache import cached_tooth_data
    from beveloid.fe.contact import FeTooth
    from beveloid.ltca.model.teeth import root_stresses
    from beveloid.names import MEMBERS
    from beveloid.rating.analysis import POSITIONS
    from beveloid.rating.root_convergence import _sizes
    from beveloid.tooth.body import body_pair
    from beveloid.tooth.sampling import ToothSampler

    print("| design | member | fillet radius / element (mm) | nodal max: default / refinement 2 (MPa) | "
          + " | ".join(label(c) for c in CANDIDATES) + " |")
    print("|---|---|---|---|" + "---|" * len(CANDIDATES))
    for spec in args.designs.split(","):
        t0 = time.perf_counter()
        pair, name = _pair(spec), Path(spec).stem
        material = ltca.Material.from_spec(pair.spec)
        moduli = {"pinion": (material.pinion_e_mpa, material.pinion_nu), "gear": (material.gear_e_mpa, material.gear_nu)}
        torque = 1500.0 if name in ("case1", "case2") else _torques(pair)[1]
        r = ltca.analyze(pair, ltca.LoadCase(torque), ltca.Options(positions=POSITIONS, tooth_model="fe"))
        flank = r.options.flank
        for m in MEMBERS:
            other = MEMBERS[1 - MEMBERS.index(m)]
            mate = FeTooth(cached_tooth_data(pair, other, *moduli[other], 1)[0], flank)
            body = body_pair(pair, m)
            geometry = getattr(body, "geometry", body)
            sampler = ToothSampler(geometry, m)
            sizes = _sizes(pair, m, 1, 1.0)
            read = {}
            for ref in (1, 2):
                raw, _ = cached_tooth_data(pair, m, *moduli[m], ref, smooth=False)
                for c, d in itertools.chain([("nodal", raw)], readouts(raw, sampler, 0.15 * geometry.normal_module_mm,
                                                                       sizes.fillet_mm, ref)):
                    tooth = FeTooth(d, flank)
                    s = root_stresses((tooth, mate) if m == "pinion" else (mate, tooth), r, r.converged)
                    read[c, ref] = float(np.nanmax(s["tension"][m]))
                    del d, tooth
                del raw
            cells = [f"{read[c, 1]:.1f} / {read[c, 2]:.1f} ({read[c, 1] / read[c, 2] - 1:+.1%})" for c in CANDIDATES]
            print(f"| {name} | {m} | {sizes.fillet_radius_mm:.3f} / {sizes.fillet_mm:.3f} | {read['nodal', 1]:.1f} / "
                  f"{read['nodal', 2]:.1f} | " + " | ".join(cells) + " |", flush=True)
        print(f"  {name}: {time.perf_counter() - t0:.0f} s", file=sys.stderr, flush=True)


def notch(args) -> None:
    from notch_benchmark import BENCH, iso_case, loads_of, material, near_spur_pair

    from beveloid.fe import plane_strain as ps
    from beveloid.fe.cache import cached_tooth_data
    from beveloid.fe.mesh import mesh_sizes
    from beveloid.tooth.sampling import ToothSampler

    print("| rack | refinement | nodal max: tip / d_en | " + " | ".join(label(c) for c in CANDIDATES) + " |")
    print("|---|---|---|" + "---|" * len(CANDIDATES))
    for name, (z, x, rho) in BENCH.items():
        pair = near_spur_pair(z, x, rho)
        loads = loads_of(iso_case(pair))
        two = ps.notch_stress(pair, "pinion", loads, ps.NotchOptions(refinement=4), material=material(pair))
        sampler = ToothSampler(pair.geometry, "pinion")
        fillet = mesh_sizes(sampler, pair.geometry.normal_module_mm, 1.0).fillet_mm
        for ref in args.refinement:
            raw, _ = cached_tooth_data(pair, "pinion", *material(pair), ref, smooth=False)
            cells = []
            for _, d in itertools.chain([(None, raw)], readouts(raw, sampler, 0.15 * pair.geometry.normal_module_mm,
                                                                fillet, ref)):
                cells.append(" / ".join(f"{ps.fe_tooth_line_load(d, pair.geometry, 'pinion', ld).max_mpa_per_n_mm / t.tension_mpa_per_n_mm:.3f}"
                                        for ld, t in zip(loads, two)))
            print(f"| {name} | {ref} | " + " | ".join(cells) + " |", flush=True)
            del raw


def main(argv=None) -> int:
    a = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    a.add_argument("--designs", default="case1,case2,R1,R2,R3")
    a.add_argument("--notch", action="store_true", help="the candidates against the 2D notch benchmark instead")
    a.add_argument("--refinement", type=int, nargs="+", default=[1, 2])
    args = a.parse_args(argv)
    (notch if args.notch else designs)(args)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

"""The FE tooth's data for the loaded contact: compliance and fillet stress per unit flank load.

``tooth_data(pair, member, material, refinement)`` meshes the member's sector
(:func:`beveloid.fe.mesh.sector_mesh`), factors it once (:mod:`beveloid.fe.solve`) and solves one
load case per node of a fixed flank grid (``GRID`` = profile x face points, on both flanks of the
loaded tooth 0): a unit force along the inward flank normal.  From the solutions:

* **Compliance** C[i, j] (mm/N): the displacement along the inward normal at grid point i per unit
  force at j, **read at a depth** d_i below the surface (the point y_i = x'_i - d_i n'_i beneath
  the node's foot x'_i, normal n'_i: the node itself, or at the face end where its normal leaves
  the solid a flank point along the face, :func:`reading_feet`) and **minus the Boussinesq
  half-space displacement** of the same point force at that point:

      C[i, j] = -n_i . u_FE(y_i; F_j) - (1 + nu) / (2 pi E R) (2 (1 - nu) + d_i^2 / R^2),
      R^2 = |x'_i - x_j|^2 + d_i^2,   d_i = min(DEPTH_PER_MODULE m_n, DEPTH_PER_THICKNESS t_i)

  (t_i the tooth's thickness at x_i: the distance to the other flank).  The FE field under a
  point force is singular at the force and, near it, mesh-dependent; read at a depth of several
  elements it has converged, and what remains after the half-space's own displacement there is
  removed is the tooth's bending, shear and rim deflection: the local flattening is left to the
  LTCA's half-space (Boussinesq/Love on the contact grid), so it is counted once.  C is symmetrised.
  Every load and reading point is located in the curved mesh (:func:`beveloid.fe.solve.locate`);
  one further than :data:`MAX_OUTSIDE_PER_FLANK_SIZE` of the flank element size from the mesh is
  an error.
* **Fillet stress**: the stress tensor (MPa per N) on both root fillets of the loaded tooth per load case,
  **read on a grid fixed by the geometry** (:func:`beveloid.fe.contact.read_grid`: sections 0.1 m_n apart
  along the face, points 0.15 fillet elements (refinement 1) apart along each section's fillet profile), each
  read point's tensor a moving least-squares fit of the nodal tensors (the mean over the tets sharing each
  node) of the fillet and the root land beside it, quadratic along the profile over +-1 fillet element and
  linear along the face over +-0.15 m_n (:func:`beveloid.fe.contact.readout_matrix`; ``smooth=False`` keeps
  the nodal means at the fillet's nodes).  The nodal means scatter from node to node by a few percent on the
  unstructured mesh, and the largest of thousands of them sits on that scatter and on where the node rows fall
  on the notch's peak (docs/loaded_contact.md 9.2, docs/validation.md 10.2); the read points are the same on
  every mesh of the member, and the fit is linear in the tensors, so superposed over a pressure field its
  principal stresses give the root stress as before.
"""
from __future__ import annotations

import math
import time
import typing
from dataclasses import dataclass, field

import numpy as np
from ..names import FLANKS
from ..tooth.sampling import ToothSampler
from ..tooth.body import body_pair
from ..tooth.departure import flank_thickness_mm
from .contact import (READ_STEP_FACE_PER_MODULE, READ_STEP_PROFILE_PER_FILLET_SIZE, read_grid, readout_matrix,
                      readout_window_mm)
from .mesh import FILLET_LANDS, mesh_sizes, sector_mesh

__all__ = ["DEPTH_PER_MODULE", "DEPTH_PER_THICKNESS", "FACE_FRACTIONS", "GRID", "MAX_OUTSIDE_PER_FLANK_SIZE",
           "LoadGrid", "ToothData", "flank_at", "load_grid", "flank_compliance", "flank_grid", "halfspace_at_depth", "reading_feet", "reading_points",
           "tooth_data"]

#: the load grid's columns along the face, as fractions of it from the toe: eight equal spans, and two
#: more columns in each end span (at 1/32 and 1/16 of the face from each end).  The LTCA's contact is
#: lumped onto the grid's nodes (bilinear weights), and a fillet node just beyond the reading depth of
#: a loaded node reads that lumped force's local stress: where a face end carries the load (a corner
#: of the flank near the start of the active profile), the root stress read there depends on the
#: column spacing.  Measured on case 1 at 1500 N m (``python benchmarks/fe_load_grid.py``): the
#: pinion's largest root stress, at its heel, with 9 equal columns 324 MPa, 17 equal columns 265,
#: these 13 columns 252, 15 end-graded columns 249; the loaded TE mean moved by 0.2 %.
FACE_FRACTIONS = (0.0, 1 / 32, 1 / 16, 1 / 8, 2 / 8, 3 / 8, 4 / 8, 5 / 8, 6 / 8, 7 / 8, 15 / 16, 31 / 32, 1.0)
#: load grid per flank: points along the profile (form limit to tip) x along the face (toe to heel)
GRID = (7, len(FACE_FRACTIONS))
DEPTH_PER_MODULE = 0.35
DEPTH_PER_THICKNESS = 0.3
#: a load or reading point further than this fraction of the flank element size from where the mesh
#: reads it is an error (:func:`beveloid.fe.solve.locate`).  The points lie on the flank or inside
#: the tooth and the curved P2 tets are located exactly: what remains is the mesh's flank face (a
#: loft through the sections, quadratic between its nodes) departing from the flank, which grows with
#: the element size h (about as h^2 from case 1's default to its coarse mesh).  Measured on the load points
#: (``python -m benchmarks.bench_fe_tooth locate``): at most 1.4e-4 h on case 1 and case 2 at the
#: default mesh, 5e-4 h at the suite's coarse one, 0.009 h on a 21-tooth, 100 mm wide pinion at
#: --fe-coarsen 8 (flank elements longer than the tooth is high); 0.05 h keeps 5 x that margin and
#: is 0.09 mm on case 1's default mesh, where the reading points read along the normal lay up to
#: 0.88 mm off the mesh.
MAX_OUTSIDE_PER_FLANK_SIZE = 0.05


@dataclass(frozen=True)
class ToothData:
    """One member's FE tooth, both flanks of the loaded tooth (index 0: left, 1: right); arrays only
    (what the cache stores)."""

    s: np.ndarray  # (ns,) profile parameter of the grid (0 form limit, 1 tip)
    z_mm: np.ndarray  # (nz,) member frame
    points_mm: np.ndarray  # (2, ns, nz, 3)
    normals: np.ndarray  # (2, ns, nz, 3) outward unit normals
    radius_mm: np.ndarray  # (2, ns, nz)
    depth_mm: np.ndarray  # (2, ns, nz) reading depth d_i
    reading_points_mm: np.ndarray  # (2, ns, nz, 3) where the approach of each node is read (inside the tooth)
    compliance_mm_per_n: np.ndarray  # (2, G, G) corrected, symmetric; G = ns nz, profile-major
    raw_compliance_mm_per_n: np.ndarray  # (2, G, G) the FE reading before the half-space is removed
    fillet_points_mm: np.ndarray  # (2, nf, 3) read points (or nodes) of the left / right fillet (padded by repeats)
    fillet_height_mm: np.ndarray  # (2, nf) above the root cone
    stress_mpa_per_n: np.ndarray  # (2 flanks loaded, 2 fillets, nf, 6, G)
    stats: np.ndarray  # [nodes, tets, free dofs, mesh s, assemble s, factor s, solve s]
    #: the read-out's window of stress_mpa_per_n (half-widths along the face, along the profile; mm): zeros for
    #: the nodal means
    smoothing_mm: np.ndarray = field(default_factory=lambda: np.zeros(2))

    STATS = ("nodes", "tets", "free_dofs", "mesh_s", "assemble_s", "factor_s", "solve_s")

    def stat(self, name: str) -> float:
        return float(self.stats[self.STATS.index(name)])


def flank_at(sampler: ToothSampler, flank: str, s, z):
    """(points (n, 3), outward normals (n, 3)) of the flank of tooth 0 at profile parameters s (n,)
    (0 form limit, 1 tip) in the sections z (n,)."""
    s, z = np.asarray(s, dtype=float).ravel(), np.asarray(z, dtype=float).ravel()
    l_tip, u_tip = sampler.flank_tip(flank, z)
    l0 = sampler.form_limits(flank, z)[0]
    l = l0 + s * (l_tip - l0)
    u = sampler.flank_u(flank, l, z, u0=u_tip)
    surf = sampler.geometry.surface(sampler.member, flank, l, u)
    return np.asarray(surf.point), np.asarray(surf.normal)


def flank_grid(sampler: ToothSampler, flank: str, grid=GRID, face_fractions=FACE_FRACTIONS):
    """(s, z, points (ns, nz, 3), outward normals (ns, nz, 3)) of the flank of tooth 0: ns equal steps of
    the profile parameter, the columns at ``face_fractions`` of the face (nz of them)."""
    ns, nz = grid
    if len(face_fractions) != nz:
        raise ValueError(f"grid {grid}: {len(face_fractions)} face fractions, not {nz}")
    s = np.linspace(0.0, 1.0, ns)
    toe, heel = sampler.z_range_mm
    lo, hi = min(toe, heel), max(toe, heel)
    z = lo + np.asarray(face_fractions, dtype=float) * (hi - lo)
    ss, zz = np.meshgrid(s, z, indexing="ij")
    points, normals = flank_at(sampler, flank, ss, zz)
    return s, z, points.reshape(ns, nz, 3), normals.reshape(ns, nz, 3)


def reading_feet(sampler: ToothSampler, flank: str, s, z, depth):
    """(feet (n, 3), their outward normals (n, 3)): the flank points beneath which the grid nodes
    (s, z) (n,) are read, at depth (n,) along the foot's inward normal.  A node's foot is the node
    itself, except where that reading point would leave the face: a helical flank's normal has an
    axial component n_z, so at one face end (the acute one) the point x - d n lies d |n_z| beyond
    the end plane, outside the solid.  There the foot moves along the face, on the node's line of
    constant profile parameter, until the reading point lies on the end plane.

    Why so: the reading point stands for the approach of the flank at the node under the load,
    beneath the surface by d so that the local flattening, left to the half-space, can be removed
    (:func:`halfspace_at_depth`: Boussinesq's displacement at depth d beneath a surface point).  The
    moved point is still at depth d beneath a flank point, its foot, and the half-space term is taken
    at that foot; the foot is the nearest flank point of the node whose normal stays inside the solid
    (0.87 mm from the node on case 1's pinion, 0.37 mm on its gear, against a grid spacing of 6.25 mm
    and a tooth that bends over lengths of its thickness).  Reading along the normal's transverse
    part instead would move every reading point, not only the face end's, off the normal of its
    node and change its depth beneath the flank."""
    s, z, d = (np.asarray(a, dtype=float).ravel() for a in (s, z, depth))
    toe, heel = sampler.z_range_mm
    lo, hi = min(toe, heel), max(toe, heel)
    feet, normals = flank_at(sampler, flank, s, z)
    zf = z.copy()
    for _ in range(4):  # the normal's axial part changes little along the face: one step nearly does
        zr = feet[:, 2] - d * normals[:, 2]
        move = np.clip(zr, lo, hi) - zr
        moved = np.abs(move) > 1e-9 * (hi - lo)
        if not moved.any():
            break
        zf[moved] += move[moved]
        feet[moved], normals[moved] = flank_at(sampler, flank, s[moved], zf[moved])
    return feet, normals


def halfspace_at_depth(surface_points, depth, e_mpa, nu, feet=None):
    """(n, n): Boussinesq's displacement along the load at depth d_i below point i (below its foot
    ``feet[i]`` when given: :func:`reading_feet`) per unit normal point force at point j on the
    surface of a half-space (mm/N)."""
    feet = surface_points if feet is None else feet
    rho2 = np.sum((feet[:, None, :] - surface_points[None, :, :]) ** 2, axis=-1)
    d = np.asarray(depth)[:, None]
    r = np.sqrt(rho2 + d * d)
    return (1 + nu) / (2 * math.pi * e_mpa * r) * (2 * (1 - nu) + d * d / (r * r))


def reading_points(feet, feet_normals, depth):
    """(..., 3) the points where the approach of the grid nodes is read: ``depth`` (..., 1) beneath
    their feet (..., 3) (:func:`reading_feet`) along the feet's inward normals (..., 3)."""
    return feet - np.asarray(depth) * feet_normals


class LoadGrid(typing.NamedTuple):
    """Both flanks' load grid (index 0: left, 1: right), its reading depths and the feet of its reading
    points (:func:`load_grid`)."""

    s: np.ndarray  # (ns,)
    z_mm: np.ndarray  # (nz,)
    points_mm: np.ndarray  # (2, ns, nz, 3)
    normals: np.ndarray  # (2, ns, nz, 3) outward
    depth_mm: np.ndarray  # (2, ns, nz)
    feet_mm: np.ndarray  # (2, ns, nz, 3)
    feet_normals: np.ndarray  # (2, ns, nz, 3) outward


def load_grid(sampler: ToothSampler, normal_module_mm: float, grid=GRID) -> LoadGrid:
    """The load grid of both flanks of tooth 0 (:func:`flank_grid`), the reading depth at each node
    (the module docstring) and the feet of the reading points (:func:`reading_feet`)."""
    grids = [flank_grid(sampler, f, grid) for f in FLANKS]
    s, z = grids[0][0], grids[0][1]
    pts = np.stack([g[2] for g in grids])
    # the other flank's grid is coarse: the thickness is a fraction of it, so an upper bound does
    thick = flank_thickness_mm(pts)
    depth = np.minimum(DEPTH_PER_MODULE * normal_module_mm, DEPTH_PER_THICKNESS * thick)
    ss, zz = np.meshgrid(s, z, indexing="ij")
    feet = [reading_feet(sampler, f, ss, zz, depth[i]) for i, f in enumerate(FLANKS)]
    return LoadGrid(s, z, pts, np.stack([g[3] for g in grids]), depth,
                    np.stack([f[0] for f in feet]).reshape(pts.shape), np.stack([f[1] for f in feet]).reshape(pts.shape))


def flank_compliance(elastic, points, normals, depth, solutions=None, feet=None, max_outside_mm=None, label="flank"):
    """(raw, corrected) compliance (mm/N) between surface points (G, 3) with outward normals (G, 3):
    unit forces along -normal at the points, the displacement along -normal read at the depths
    (G,) below them (below their feet when ``feet`` = (points, outward normals), (G, 3) each, is
    given: :func:`reading_feet`); corrected = raw - :func:`halfspace_at_depth` (the module
    docstring).  ``max_outside_mm``: a load or reading point further than this from where the mesh
    reads it is an error (:func:`beveloid.fe.solve.locate`, named by ``label``).  Returns also the
    solutions (ndofs, G) for the stresses."""
    foot, foot_n = (points, normals) if feet is None else feet
    g = len(points)
    from . import solve  # here: scipy.sparse and scipy.spatial only where FE data is made, not where it is read

    located = solve.locate(elastic.mesh, np.vstack([points, reading_points(foot, foot_n, depth[:, None])]), max_outside_mm,
                           label=[f"{label} load point"] * g + [f"{label} reading point"] * g, geometry=elastic.geometry)
    load = solve.displacement_operator(elastic, located[:g], -normals)
    read = solve.displacement_operator(elastic, located[g:], -normals)
    u = elastic.solve(load.T.toarray()) if solutions is None else solutions
    raw = read @ u
    corrected = raw - halfspace_at_depth(points, depth, elastic.e_mpa, elastic.nu, foot)
    return raw, 0.5 * (corrected + corrected.T), u


#: the stages tooth_data reports to its progress (beveloid.progress.Progress)
STAGES = 3


def _say(progress, stage, text):
    if progress is not None:
        progress(stage, STAGES, text)


def tooth_data(pair, member: str, e_mpa: float, nu: float, refinement: int = 1, progress=None, coarsen=1.0,
               smooth: bool | float | tuple = True) -> ToothData | tuple:
    """Mesh, factor and solve the member's FE tooth (see the module docstring): on its body, the member
    cut by the unmodified rack (:mod:`beveloid.tooth.body`).  ``smooth``: the fillet stresses read on the
    member's read grid (the default: what the LTCA and the rating read) or the nodal means at the fillet's
    nodes; a number: read on the grid through the window of this mesh coarsened that many times
    (:func:`beveloid.fe.contact.readout_window_mm` of its fillet elements), where wider than its own: the
    rating's convergence check reads the default mesh and a coarsened one through the same window
    (:mod:`beveloid.rating.root_convergence`); a tuple of these: a tuple of ToothData, one per read-out in
    that order, from one mesh and one solve (they differ in ``stress_mpa_per_n``, ``fillet_points_mm``,
    ``fillet_height_mm`` and ``smoothing_mm`` only; each the same numbers as its own call)."""
    from . import solve  # (as flank_compliance)

    pair = body_pair(pair, member)
    geometry = getattr(pair, "geometry", pair)
    t0 = time.perf_counter()
    _say(progress, 0, f"FE tooth {member}: meshing (refinement {refinement})")
    mesh = sector_mesh(pair, member, refinement=refinement, coarsen=coarsen)
    t1 = time.perf_counter()
    _say(progress, 1, f"FE tooth {member}: {mesh.nodes.shape[0]} nodes, {mesh.tets.shape[0]} tets; factorising")
    elastic = solve.factorise(mesh, e_mpa, nu)
    sampler = ToothSampler(geometry, member)
    grid = load_grid(sampler, geometry.normal_module_mm)
    s, z, pts, nrm, depth = grid.s, grid.z_mm, grid.points_mm, grid.normals, grid.depth_mm.reshape(2, -1)
    G = pts.shape[1] * pts.shape[2]
    flat_p, flat_n = pts.reshape(2, G, 3), nrm.reshape(2, G, 3)
    fillet_nodes = [mesh.node_sets[f"fillet_{f}_0"] for f in FLANKS]
    fe1 = mesh_sizes(sampler, geometry.normal_module_mm, 1.0).fillet_mm
    outs = [_read_out(mesh, sampler, geometry.normal_module_mm, fe1, refinement, fillet_nodes, s_)
            for s_ in (smooth if isinstance(smooth, tuple) else (smooth,))]
    # the nodal tensors once per set of fit nodes (the read grid's and the nodal means' differ), each read-out
    # applied to them
    node_sets = {}
    for o in outs:
        node_sets.setdefault(o.nodes_key, o.fit_nodes)
    stress_ops = {k: [solve.stress_operator(elastic, nodes) for nodes in v] for k, v in node_sets.items()}
    _say(progress, 2, f"FE tooth {member}: {elastic.timings_s['free_dofs']} dofs factorised in "
                   f"{elastic.timings_s['factor_s']:.1f} s; solving {2 * G} load cases")
    t2 = time.perf_counter()
    stresses = [np.zeros((2, 2, max(len(p) for p in o.reads), 6, G)) for o in outs]
    comp, raw = np.zeros((2, G, G)), np.zeros((2, G, G))
    reading = reading_points(grid.feet_mm, grid.feet_normals, grid.depth_mm[..., None])
    for f in range(2):
        feet = (grid.feet_mm[f].reshape(G, 3), grid.feet_normals[f].reshape(G, 3))
        raw[f], comp[f], u = flank_compliance(elastic, flat_p[f], flat_n[f], depth[f], feet=feet,
                                              max_outside_mm=MAX_OUTSIDE_PER_FLANK_SIZE * mesh.sizes.flank_mm,
                                              label=f"FE tooth {member}, {FLANKS[f]} flank")
        for side in range(2):
            nodal = {k: (ops[side] @ u).reshape(-1, 6 * G) for k, ops in stress_ops.items()}
            for o, stress in zip(outs, stresses):
                sig = nodal[o.nodes_key]
                if o.fits[side] is not None:
                    sig = o.fits[side] @ sig
                sig = sig.reshape(-1, 6, G)
                stress[f, side, :sig.shape[0]] = sig
                stress[f, side, sig.shape[0]:] = sig[-1]
    t3 = time.perf_counter()
    _say(progress, STAGES, f"FE tooth {member}: done in {t3 - t0:.1f} s")
    stats = np.array([mesh.nodes.shape[0], mesh.tets.shape[0], elastic.timings_s["free_dofs"], t1 - t0,
                      elastic.timings_s["assemble_s"], elastic.timings_s["factor_s"], t3 - t2], dtype=float)
    data = []
    for o, stress in zip(outs, stresses):
        fp = np.zeros((2, stress.shape[2], 3))
        for side, p in enumerate(o.reads):
            fp[side, :len(p)] = p
            fp[side, len(p):] = p[-1]
        height = np.hypot(fp[..., 0], fp[..., 1]) - sampler.root_radius_mm(fp[..., 2])
        data.append(ToothData(s=s, z_mm=z, points_mm=pts, normals=nrm, radius_mm=np.hypot(pts[..., 0], pts[..., 1]),
                              depth_mm=grid.depth_mm, reading_points_mm=reading, compliance_mm_per_n=comp,
                              raw_compliance_mm_per_n=raw, fillet_points_mm=fp, fillet_height_mm=height,
                              stress_mpa_per_n=stress, stats=stats, smoothing_mm=o.window))
    return tuple(data) if isinstance(smooth, tuple) else data[0]


class _ReadOut(typing.NamedTuple):
    """One read-out of the fillet stresses (:func:`_read_out`)."""

    window: np.ndarray  # (2,) the window's half-widths mm (zeros: the nodal means)
    nodes_key: bool  # the fit nodes' set: True the fillets and their root lands, False the fillets' nodes
    fit_nodes: list  # per fillet (left, right): the mesh nodes whose tensors are read
    fits: list  # per fillet: the read-out's matrix (read points x fit nodes), None for the nodal means
    reads: list  # per fillet: the points read (n, 3)


def _read_out(mesh, sampler, normal_module_mm, fe1, refinement, fillet_nodes, smooth) -> _ReadOut:
    """The read-out ``smooth`` of :func:`tooth_data` on ``mesh`` (``fe1``: the member's fillet elements at
    refinement 1)."""
    if not smooth:
        return _ReadOut(np.zeros(2), False, fillet_nodes, [None, None], [mesh.nodes[n] for n in fillet_nodes])
    # the read-out (fe.contact.readout_matrix): each fillet's nodes and those of the root land beside it
    # (a sharp rack's trochoid meets the land tangentially near where its stress peaks) fitted around the
    # points of a read grid fixed by the geometry
    own = mesh.sizes.fillet_mm
    if not isinstance(smooth, bool):  # the window of the mesh coarsened that many times
        own = max(own, mesh_sizes(sampler, normal_module_mm, refinement / float(smooth)).fillet_mm)
    window = np.array(readout_window_mm(normal_module_mm, fe1, own))
    fit_nodes = [np.union1d(nodes, mesh.node_sets[FILLET_LANDS[f]]) for nodes, f in zip(fillet_nodes, FLANKS)]
    grids = [read_grid(sampler, f, READ_STEP_FACE_PER_MODULE * normal_module_mm,
                       READ_STEP_PROFILE_PER_FILLET_SIZE * fe1) for f in FLANKS]
    fits = [readout_matrix(*g, mesh.nodes[n], *window) for g, n in zip(grids, fit_nodes)]
    return _ReadOut(window, True, fit_nodes, fits, [g[0] for g in grids])

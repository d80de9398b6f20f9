"""The FE tooth's data for the loaded contact: compliance and fillet stress per unit flank load.

``tooth_data(pair, member, material, refinement)`` meshes the member's sector
(:func:`beveloid.fe.mesh.sector_mesh`), factors it once (:mod:`beveloid.fe.solve`) and solves one
load case per node of a fixed flank grid (``GRID`` = profile x face points, on both flanks of the
loaded tooth 0): a unit force along the inward flank normal.  From the solutions:

* **Compliance** C[i, j] (mm/N): the displacement along the inward normal at grid point i per unit
  force at j, **read at a depth** d_i below the surface (the point x_i - d_i n_i) and **minus the
  Boussinesq half-space displacement** of the same point force at that point:

      C[i, j] = -n_i . u_FE(x_i - d_i n_i; F_j) - (1 + nu) / (2 pi E R) (2 (1 - nu) + d_i^2 / R^2),
      R^2 = |x_i - x_j|^2 + d_i^2,   d_i = min(DEPTH_PER_MODULE m_n, DEPTH_PER_THICKNESS t_i)

  (t_i the tooth's thickness at x_i: the distance to the other flank).  The FE field under a
  point force is singular at the force and, near it, mesh-dependent; read at a depth of several
  elements it has converged, and what remains after the half-space's own displacement there is
  removed is the tooth's bending, shear and rim deflection: the local flattening is left to the
  LTCA's half-space (Boussinesq/Love on the contact grid), so it is counted once.  C is symmetrised.
* **Fillet stress**: the stress tensor (MPa per N) at every node of both root fillets of the
  loaded tooth (mean over the tets sharing it), per load case.  Superposed over a pressure field
  (linear) its principal stresses give the root stress.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
from ..names import FLANKS
from ..tooth.sampling import ToothSampler
from ..tooth.body import body_pair, flank_thickness_mm
from . import solve
from .mesh import sector_mesh

__all__ = ["DEPTH_PER_MODULE", "DEPTH_PER_THICKNESS", "GRID", "ToothData", "flank_compliance", "flank_grid",
           "halfspace_at_depth", "tooth_data"]

#: load grid per flank: points along the profile (form limit to tip) x along the face (toe to heel)
GRID = (7, 9)
DEPTH_PER_MODULE = 0.35
DEPTH_PER_THICKNESS = 0.3


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
    compliance_mm_per_n: np.ndarray  # (2, G, G) corrected, symmetric; G = ns nz, profile-major
    raw_compliance_mm_per_n: np.ndarray  # (2, G, G) the FE reading before the half-space is removed
    fillet_points_mm: np.ndarray  # (2, nf, 3) nodes of the left / right fillet (padded by repeats)
    fillet_height_mm: np.ndarray  # (2, nf) above the root cone
    stress_mpa_per_n: np.ndarray  # (2 flanks loaded, 2 fillets, nf, 6, G)
    stats: np.ndarray  # [nodes, tets, free dofs, mesh s, assemble s, factor s, solve s]

    STATS = ("nodes", "tets", "free_dofs", "mesh_s", "assemble_s", "factor_s", "solve_s")

    def stat(self, name: str) -> float:
        return float(self.stats[self.STATS.index(name)])


def flank_grid(sampler: ToothSampler, flank: str, grid=GRID):
    """(s, z, points (ns, nz, 3), outward normals (ns, nz, 3)) of the flank of tooth 0."""
    ns, nz = grid
    s = np.linspace(0.0, 1.0, ns)
    toe, heel = sampler.z_range_mm
    z = np.linspace(min(toe, heel), max(toe, heel), nz)
    l_tip, u_tip = sampler.flank_tip(flank, z)
    l0 = sampler.form_limits(flank, z)[0][None, :]
    l = l0 + s[:, None] * (l_tip[None, :] - l0)
    u = sampler.flank_u(flank, l, z[None, :], u0=u_tip[None, :])
    surf = sampler.geometry.surface(sampler.member, flank, l, u)
    return s, z, np.asarray(surf.point), np.asarray(surf.normal)


def halfspace_at_depth(surface_points, depth, e_mpa, nu):
    """(n, n): Boussinesq's displacement along the load at depth d_i below point i per unit normal
    point force at point j on the surface of a half-space (mm/N)."""
    rho2 = np.sum((surface_points[:, None, :] - surface_points[None, :, :]) ** 2, axis=-1)
    d = np.asarray(depth)[:, None]
    r = np.sqrt(rho2 + d * d)
    return (1 + nu) / (2 * math.pi * e_mpa * r) * (2 * (1 - nu) + d * d / (r * r))


def flank_compliance(elastic, points, normals, depth, solutions=None):
    """(raw, corrected) compliance (mm/N) between surface points (G, 3) with outward normals (G, 3):
    unit forces along -normal at the points, the displacement along -normal read at the depths
    (G,) below them; corrected = raw - :func:`halfspace_at_depth` (the module docstring).  Returns
    also the solutions (ndofs, G) for the stresses."""
    mesh = elastic.mesh
    load = solve.displacement_operator(elastic, solve.locate(mesh, points), -normals)
    read = solve.displacement_operator(elastic, solve.locate(mesh, points - depth[:, None] * normals), -normals)
    u = elastic.solve(load.T.toarray()) if solutions is None else solutions
    raw = read @ u
    corrected = raw - halfspace_at_depth(points, depth, elastic.e_mpa, elastic.nu)
    return raw, 0.5 * (corrected + corrected.T), u


def _say(progress, text):
    if progress is not None:
        progress(text)


def tooth_data(pair, member: str, e_mpa: float, nu: float, refinement: int = 1, progress=None, coarsen=1.0
               ) -> ToothData:
    """Mesh, factor and solve the member's FE tooth (see the module docstring): on its body, the member
    cut by the unmodified rack (:mod:`beveloid.tooth.body`)."""
    pair = body_pair(pair, member)
    geometry = getattr(pair, "geometry", pair)
    t0 = time.perf_counter()
    _say(progress, f"FE tooth {member}: meshing (refinement {refinement})")
    mesh = sector_mesh(pair, member, refinement=refinement, coarsen=coarsen)
    t1 = time.perf_counter()
    _say(progress, f"FE tooth {member}: {mesh.nodes.shape[0]} nodes, {mesh.tets.shape[0]} tets; factorising")
    elastic = solve.factorise(mesh, e_mpa, nu)
    sampler = ToothSampler(geometry, member)
    grids = [flank_grid(sampler, f) for f in FLANKS]
    s, z = grids[0][0], grids[0][1]
    pts = np.stack([g[2] for g in grids])
    nrm = np.stack([g[3] for g in grids])
    G = pts.shape[1] * pts.shape[2]
    flat_p, flat_n = pts.reshape(2, G, 3), nrm.reshape(2, G, 3)
    thick = flank_thickness_mm(flat_p)
    # the other flank's grid is coarse: the thickness is a fraction of it, so an upper bound does
    depth = np.minimum(DEPTH_PER_MODULE * geometry.normal_module_mm, DEPTH_PER_THICKNESS * thick)
    fillet_nodes = [mesh.node_sets[f"fillet_{f}_0"] for f in FLANKS]
    stress_ops = [solve.stress_operator(elastic, nodes) for nodes in fillet_nodes]
    _say(progress, f"FE tooth {member}: {elastic.timings_s['free_dofs']} dofs factorised in "
                   f"{elastic.timings_s['factor_s']:.1f} s; solving {2 * G} load cases")
    t2 = time.perf_counter()
    nf = max(len(n) for n in fillet_nodes)
    stress = np.zeros((2, 2, nf, 6, G))
    comp, raw = np.zeros((2, G, G)), np.zeros((2, G, G))
    for f in range(2):
        raw[f], comp[f], u = flank_compliance(elastic, flat_p[f], flat_n[f], depth[f])
        for side in range(2):
            sig = (stress_ops[side] @ u).reshape(-1, 6, G)
            stress[f, side, :sig.shape[0]] = sig
            stress[f, side, sig.shape[0]:] = sig[-1]
    t3 = time.perf_counter()
    fp = np.zeros((2, nf, 3))
    for side, nodes in enumerate(fillet_nodes):
        fp[side, :len(nodes)] = mesh.nodes[nodes]
        fp[side, len(nodes):] = mesh.nodes[nodes[-1]]
    height = np.hypot(fp[..., 0], fp[..., 1]) - sampler.root_radius_mm(fp[..., 2])
    _say(progress, f"FE tooth {member}: done in {t3 - t0:.1f} s")
    stats = np.array([mesh.nodes.shape[0], mesh.tets.shape[0], elastic.timings_s["free_dofs"], t1 - t0,
                      elastic.timings_s["assemble_s"], elastic.timings_s["factor_s"], t3 - t2], dtype=float)
    return ToothData(s=s, z_mm=z, points_mm=pts, normals=nrm, radius_mm=np.hypot(pts[..., 0], pts[..., 1]),
                     depth_mm=depth.reshape(2, *pts.shape[1:3]), compliance_mm_per_n=comp,
                     raw_compliance_mm_per_n=raw, fillet_points_mm=fp, fillet_height_mm=height,
                     stress_mpa_per_n=stress, stats=stats)

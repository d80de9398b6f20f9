"""The contact pattern over the cycle on each member's flank: the max pressure on a flank raster."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..generated import flank_boundaries

RASTER = (48, 96)  #: (l, u) nodes of the flank raster


@dataclass
class FlankPattern:
    """Max pressure over the cycle on a raster of one member's flank (tooth 0)."""

    member: str
    points: np.ndarray  # (n, 3) raster nodes on the flank, member frame
    weight_mm2: np.ndarray  # (n,) area of each node's raster cell
    max_pressure_mpa: np.ndarray  # (n,) 0 where never loaded
    area_fraction: float | None


def _flank_raster(geom, flank, member, shape):
    """Nodes of a (l, u) raster covering the member's flank between its four boundaries."""
    m = geom.member(member)
    mn = geom.normal_module_mm
    lo_l, hi_l = 0.0, 3.0 * (m.cutter_addendum_mm + m.tip_height_mm) / math.cos(geom.normal_pressure_angle)
    half_u = 1.5 * m.face_width_mm / max(math.cos(m.helix_angle), 0.3) + 4 * mn
    box = (lo_l, hi_l, -half_u, half_u)
    for n_l, n_u in ((40, 80), shape):
        l = np.linspace(box[0], box[1], n_l)
        u = np.linspace(box[2], box[3], n_u)
        L, U = np.meshgrid(l, u, indexing="ij")
        jet = geom.surface_jet(member, flank, L, U)
        margin = flank_boundaries.flank_margins(jet.point, L, m.blank()).margins.min(axis=-1)
        inside = margin >= 0
        if not inside.any():
            return None
        il, iu = np.nonzero(inside)
        dl, du = l[1] - l[0], u[1] - u[0]
        box = (max(lo_l, l[il.min()] - dl), l[il.max()] + dl, u[iu.min()] - du, u[iu.max()] + du)
    cell = (l[1] - l[0]) * (u[1] - u[0])
    weight = np.linalg.norm(np.cross(jet.point_D_lu[..., 0], jet.point_D_lu[..., 1]), axis=-1) * cell
    return jet.point[inside], weight[inside]


def flank_pattern(result, geom, member, raster=RASTER) -> FlankPattern:
    """The union over the cycle of the loaded cells, with the max pressure, on a flank raster.

    Between two computed positions each pair's patch is swept by translating it with the
    tangency point (sub-steps no longer than a cell across), so a patch narrower than its
    travel between positions still paints a band, as the paper's patterns do.
    """
    from scipy.spatial import cKDTree

    r = _flank_raster(geom, result.flank, member, raster)
    if r is None:
        return FlankPattern(member, np.zeros((0, 3)), np.zeros(0), np.zeros(0), None)
    nodes, weight = r
    pts = result.gap.pinion_point if member == "pinion" else result.gap.gear_point  # (N, P, cells, 3)
    p = np.where(result.converged[:, None, None], result.pressure_mpa, 0.0)
    hx = result.grid.across_half_mm / result.grid.across_cells  # (N, P) half cell widths
    hy = result.grid.along_half_mm / result.grid.along_cells
    reach = float(np.max(np.hypot(hx, hy))) * 1.05
    clouds, values = [], []
    N, P = p.shape[:2]
    for j in range(N):
        for k in range(P):
            on = p[j, k] > 0
            if not on.any():
                continue
            base = pts[j, k, on]
            clouds.append(base)
            values.append(p[j, k, on])
            if j + 1 < N and result.converged[j + 1]:
                centre = np.average(base, axis=0, weights=p[j, k, on])
                on2 = p[j + 1, k] > 0
                if on2.any():
                    shift = np.average(pts[j + 1, k, on2], axis=0, weights=p[j + 1, k, on2]) - centre
                    steps = int(min(50, math.ceil(np.linalg.norm(shift) / (2 * hx[j, k]))))
                    for s in range(1, steps):
                        clouds.append(base + shift * (s / steps))
                        values.append(p[j, k, on])
    if not clouds:
        return FlankPattern(member, nodes, weight, np.zeros(len(nodes)), 0.0)
    cloud = np.concatenate(clouds)
    val = np.concatenate(values)
    tree = cKDTree(cloud)
    dist, idx = tree.query(nodes, k=min(6, len(cloud)), distance_upper_bound=reach)
    dist, idx = np.atleast_2d(dist.T).T, np.atleast_2d(idx.T).T
    valx = np.append(val, 0.0)
    pmax = np.where(np.isfinite(dist), valx[np.minimum(idx, len(val))], 0.0).max(axis=-1)
    frac = float(weight[pmax > 0].sum() / weight.sum())
    return FlankPattern(member, nodes, weight, pmax, frac)

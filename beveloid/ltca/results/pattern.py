"""The loaded contact pattern: the maximum pressure over the mesh cycle on a raster of each
member's flank, as a measured contact pattern shows it.

Each computed position's pressure field of each pair is interpolated bilinearly at the raster
nodes (a node's grid coordinates come from the affine map that takes the cells' flank points to
their grid coordinates, fitted per (position, pair): exact on the pinion, whose cells are defined
by it; first order on the gear).  Between two computed positions the mesh moves continuously: the
field of position j is carried towards position j+1 by the displacement of the pair's pressure
centroid and blended linearly with the field of j+1 carried back (sub-steps of half the smaller
patch width), so the envelope is a continuous band, not stripes at the computed positions.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...generated import flank_boundaries

RASTER = (64, 128)  #: (l, u) nodes of the flank raster
MAX_SUBSTEPS = 200
#: raster points per evaluation of a field between computed positions (sub-steps batched up to it)
BATCH_POINTS = 16384


@dataclass(frozen=True)
class FlankPattern:
    """Max pressure over the cycle on a raster of one member's flank (tooth 0)."""

    member: str
    points: np.ndarray  # (n, 3) raster nodes on the flank, member frame
    weight_mm2: np.ndarray  # (n,) area of each node's raster cell
    max_pressure_mpa: np.ndarray  # (n,) 0 where never loaded
    area_fraction: float | None
    raster_points: np.ndarray = None  # (n_l, n_u, 3) every raster node (also off the flank)
    raster_inside: np.ndarray = None  # (n_l, n_u) on the flank
    raster_pressure_mpa: np.ndarray = None  # (n_l, n_u) max pressure, 0 off the flank


def _flank_raster(geom, flank, member, shape):
    """(points (n_l, n_u, 3), inside, weight) of a (l, u) raster covering the member's flank
    between its four boundaries; None if no node lies on it."""
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
        with np.errstate(invalid="ignore"):
            margin = flank_boundaries.flank_margins(jet.point, L, m.blank()).margins.min(axis=-1)
        inside = margin >= 0
        if not inside.any():
            return None
        il, iu = np.nonzero(inside)
        dl, du = l[1] - l[0], u[1] - u[0]
        box = (max(lo_l, l[il.min()] - dl), l[il.max()] + dl, u[iu.min()] - du, u[iu.max()] + du)
    cell = (l[1] - l[0]) * (u[1] - u[0])
    weight = np.linalg.norm(np.cross(jet.point_D_lu[..., 0], jet.point_D_lu[..., 1]), axis=-1) * cell
    return jet.point, inside, weight


class _Cells:
    """What the field of one (position, pair) takes from the grid and the pressure, whichever member's flank it
    is drawn on (:func:`flank_patterns` computes it once for both members)."""

    def __init__(self, result, j, k):
        g = result.grid
        self.nx, self.ny = g.across_cells, g.along_cells
        self.X, self.Y = float(g.across_half_mm[j, k]), float(g.along_half_mm[j, k])
        self.p = result.pressure_mpa[j, k].reshape(self.nx, self.ny)
        self.shift = result.gap.across_shift_mm[j, k]
        self.x, self.y = result.cell_coordinates_mm(j, k)
        self.in_flank = result.gap.in_flank[j, k].reshape(self.nx, self.ny)
        yc = np.linspace(-self.Y, self.Y, self.ny + 1)
        self.yc = 0.5 * (yc[1:] + yc[:-1])  # the along cells' centres
        self.padded = np.pad(self.p, 1)  # a ring of zero pressure about the grid
        # the box in grid coordinates outside which the field is zero: within one cell of a loaded cell
        # (the bilinear weights' reach), the columns' offsets at their extremes; a margin far above the
        # rounding of the coordinates
        li, lj = np.nonzero(self.p > 0)
        if li.size:
            dx, dy = 2.0 * self.X / self.nx, 2.0 * self.Y / self.ny
            lo = np.array([-self.X + li.min() * dx - dx + min(self.shift.min(), 0.0),
                           -self.Y + lj.min() * dy - dy])
            hi = np.array([-self.X + (li.max() + 1) * dx + dx + max(self.shift.max(), 0.0),
                           -self.Y + (lj.max() + 1) * dy + dy])
            pad = 1e-6 * (hi - lo) + 1e-9
            self.box = (lo - pad, hi + pad)
        else:
            self.box = None


class _Field:
    """The pressure of one (position, pair) as a function of member-frame points near its flank: its
    :class:`_Cells` and the affine map from the member's points to them."""

    def __init__(self, cells, points, j, k):
        self.nx, self.ny, self.X, self.Y = cells.nx, cells.ny, cells.X, cells.Y
        self.p, self.shift, self.yc, self.padded, self.box = cells.p, cells.shift, cells.yc, cells.padded, cells.box
        x, y = cells.x, cells.y
        pts = points[j, k].reshape(self.nx, self.ny, 3)
        ok = np.isfinite(pts).all(axis=-1) & cells.in_flank
        P, c = pts[ok], np.stack([x[ok], y[ok]], axis=-1)
        self.centre = P.mean(axis=0)
        self.c0 = c.mean(axis=0)
        # the affine map member frame -> grid coordinates, least squares over the cells on the flanks
        self.map = np.linalg.lstsq(P - self.centre, c - self.c0, rcond=None)[0]  # (3, 2)
        w = self.p[ok]
        self.centroid = (P * w[:, None]).sum(axis=0) / w.sum() if w.sum() > 0 else self.centre
        self.half_width = 2.0 * max(self.X, 1e-6)

    def coordinates(self, q):
        """(n, 2) the grid coordinates of member-frame points q (n, 3)."""
        return (q - self.centre) @ self.map + self.c0

    def reached(self, c, move):
        """(n,) the points of grid coordinates c (n, 2) (:meth:`coordinates`) at which the field can be
        non-zero once moved by t x ``move`` (3,), t in [0, 1]: its box swept along the move (a superset:
        the box of the swept box)."""
        if self.box is None:
            return np.zeros(len(c), dtype=bool)
        d = np.asarray(move) @ self.map
        lo, hi = self.box
        lo, hi = np.minimum(lo, lo + d), np.maximum(hi, hi + d)
        x, y = c[:, 0], c[:, 1]
        return (x >= lo[0]) & (x <= hi[0]) & (y >= lo[1]) & (y <= hi[1])

    def at(self, c):
        """(n,) the pressure at the grid coordinates c (n, 2) (:meth:`coordinates`)."""
        xu = c[:, 0] - np.interp(c[:, 1], self.yc, self.shift)
        fi = (xu / self.X + 1.0) * self.nx / 2 - 0.5
        fj = (c[:, 1] / self.Y + 1.0) * self.ny / 2 - 0.5
        inside = (fi > -1) & (fi < self.nx) & (fj > -1) & (fj < self.ny)
        out = np.zeros(len(c))  # 0 off the grid; the bilinear pressure only where it is needed
        fi, fj = fi[inside], fj[inside]
        i0, j0 = np.floor(fi).astype(int), np.floor(fj).astype(int)
        a, b = fi - i0, fj - j0
        i0, j0 = np.clip(i0 + 1, 0, self.nx), np.clip(j0 + 1, 0, self.ny)
        padded = self.padded
        out[inside] = ((1 - a) * (1 - b) * padded[i0, j0] + a * (1 - b) * padded[i0 + 1, j0]
                       + (1 - a) * b * padded[i0, j0 + 1] + a * b * padded[i0 + 1, j0 + 1])
        return out


def flank_patterns(result, geom, members=("pinion", "gear"), raster=RASTER, rasters=None) -> dict:
    """{member: :func:`flank_pattern`} of ``members``, each field's grid and pressure (:class:`_Cells`) taken
    once for all of them; ``rasters``: as :func:`flank_pattern`'s."""
    cells = {}
    return {m: flank_pattern(result, geom, m, raster, cells=cells, rasters=rasters) for m in members}


def flank_pattern(result, geom, member, raster=RASTER, *, cells=None, rasters=None) -> FlankPattern:
    """The maximum pressure over the cycle on a raster of one member's flank (see the module docstring).
    ``cells``: a dict that keeps each (position, pair)'s :class:`_Cells` for the next member's pattern of the same
    result (:func:`flank_patterns`).  ``rasters``: a dict that keeps the member's flank raster (it depends on the
    geometry alone) for the patterns of other results of the same ``geom`` (the torques of ``beveloid ltca``:
    ``ltca.studies.nominal_results``)."""
    cells = {} if cells is None else cells
    key = (member, result.flank, tuple(raster))
    if rasters is not None and key in rasters:
        r = rasters[key]
    else:
        r = _flank_raster(geom, result.flank, member, raster)
        if rasters is not None:
            rasters[key] = r
    if r is None:
        return FlankPattern(member, np.zeros((0, 3)), np.zeros(0), np.zeros(0), None)
    grid_points, inside, weight = r
    nodes = grid_points[inside]
    pts = result.gap.pinion_point if member == "pinion" else result.gap.gear_point  # (N, P, cells, 3)
    ok = result.converged
    N, P = result.pressure_mpa.shape[:2]
    pmax = np.zeros(len(nodes))
    fields, at = {}, {}
    for j in range(N):
        for k in range(P):
            if ok[j] and result.pressure_mpa[j, k].max() > 0:
                if (j, k) not in cells:
                    cells[j, k] = _Cells(result, j, k)
                f = fields[j, k] = _Field(cells[j, k], pts, j, k)
                at[j, k] = f.coordinates(nodes)
                idx = np.flatnonzero(f.reached(at[j, k], np.zeros(3)))  # the field is 0 at the others
                pmax[idx] = np.maximum(pmax[idx], f.at(at[j, k][idx]))
    for (j, k), f in fields.items():
        g = fields.get((j + 1, k))
        if g is None:
            continue
        delta = g.centroid - f.centroid
        dist = float(np.linalg.norm(delta))
        if dist == 0:
            continue
        reach = dist + 2 * max(f.Y, g.Y)
        # only the nodes that either field can reach on the way: the others stay as they are (0 from both)
        idx = np.flatnonzero(f.reached(at[j, k], delta) | g.reached(at[j + 1, k], -delta))
        idx = idx[np.linalg.norm(nodes[idx] - 0.5 * (f.centroid + g.centroid), axis=-1) < reach]
        if idx.size == 0:
            continue
        steps = int(min(MAX_SUBSTEPS, math.ceil(dist / (0.5 * min(f.X, g.X)))))
        best = pmax[idx]
        # the nodes' grid coordinates in each field, moved with it: a field's map is affine, so a node's
        # coordinates once the field has moved by t x delta are those at rest less t x (delta's image)
        cf, df = at[j, k][idx], delta @ f.map
        cg, dg = at[j + 1, k][idx], delta @ g.map
        # the sub-steps t = s / steps, several per call of the fields (about BATCH_POINTS points a call)
        per = max(1, BATCH_POINTS // len(idx))
        for s0 in range(1, steps, per):
            t = (np.arange(s0, min(steps, s0 + per)) / steps)[:, None, None]
            both = ((1 - t[..., 0]) * f.at((cf - t * df).reshape(-1, 2)).reshape(len(t), -1)
                    + t[..., 0] * g.at((cg + (1 - t) * dg).reshape(-1, 2)).reshape(len(t), -1))
            best = np.maximum(best, both.max(axis=0))
        pmax[idx] = best
    frac = float(weight[inside][pmax > 0].sum() / weight[inside].sum())
    full = np.zeros(inside.shape)
    full[inside] = pmax
    return FlankPattern(member, nodes, weight[inside], pmax, frac, grid_points, inside, full)

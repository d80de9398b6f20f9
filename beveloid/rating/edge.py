"""The edge-contact measure of the verdict (docs/rating.md 6): the share of the mesh's load carried
within a band of fixed width along a flank edge, a quantity that converges with the contact grid and the
positions where the edge's own peak pressure does not (issue 57.2).

A sharp flank edge (a face end, a tip) pressed into the mating flank is a punch corner: its pressure
grows like d^-1/2 towards the edge and the largest cell pressure grows without bound as the grid is
refined (1205 / 1616 / 2049 / 2860 MPa on case 1 at 300 N m for grids 7x11 / 11x17 / 15x25 / 21x33).
The force within a distance delta of the edge is an integral of that field and converges; over the
mesh's load at that instant it says how much of the load the pattern puts on the edge: a pattern that
stays on the flank puts none there.  delta is a physical length, :data:`BAND_MODULES` times the normal
module, the order of an unrelieved edge's break (a deburred or chamfered tooth end or tip).  The band's
mean pressure (that force over the loaded area within delta) is reported beside it.

Each cell's share of the band comes from its footprint in the distance to the edge, as ``face_load``
spreads a cell over the face: over a pair's grid the distance is affine in the grid coordinates (least
squares over the pair's cells), a cell of widths dx, dy covers the distance interval of two uniform
spreads |g_x| dx, |g_y| dy (a trapezoid).  The cell's force acts on the flank only: the part of a
footprint that lies beyond the edge (a cell whose centre is on the flank near it) carries none, and the
force is spread over the footprint's part on the flank (:func:`band_fractions`).  Counted in the band
instead, that part put up to half an edge cell's force within delta: at a face end, where the distance
runs along the contact line and a cell's footprint there is 1.5-6 mm against delta's 0.25 mm, the
share followed the cell's length (design K of ``benchmarks/rating_invariance.py`` on the plate tooth
at 130 N m: 0.049 / 0.037 / 0.028 / 0.024 at grids 7x11 / 11x17 / 15x25 / 21x33; on the flank only
0.022 / 0.022 / 0.020 / 0.019; ``benchmarks/edge_band_convergence.py``).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..names import MEMBERS
from ..tooth import sections
from .face_load import _affine_slopes, _trapezoid_cdf

__all__ = ["BAND_MODULES", "PROFILES", "SURFACE_BAND_MODULES", "SURFACE_REACH", "EdgeDistances", "EdgeLoad",
           "band_fractions", "edge_loads", "edge_shares",
           "surface_peaks"]

#: the band's width over the normal module (this work's choice: an edge break of 0.1 m_n, a band of
#: half of it, where the sharp edge's pressure is still above the flank's)
BAND_MODULES = 0.05
#: the verdict's local contact pressure (S_H) is read beyond this over the normal module from every edge:
#: nearer a sharp edge, and most in a corner of two, the pressure carries the edge's d^-1/2 tail, and where
#: the edge crosses the contact lines at a shallow angle (a patch pushed into the corner of a tip and an end)
#: that tail and the load rising towards the corner run over many cells: read there, the largest pressure
#: grows as the grid is refined (docs/rating.md 5; design M of docs/validation.md 10.1 beyond 0.1 / 0.2 / 0.3 /
#: 0.5 m_n: 827-973 / 787-921 / 773-882 / 740-803 MPa over the grids 7x11 to 21x33)
SURFACE_BAND_MODULES = 0.5
#: S_H is read on cells more than this many cells (8-neighbourhood) from an off-flank cell; the bands of
#: the toe, heel and tip, lengths, bound it there
SURFACE_REACH = 1
#: the edges of a member's flank
EDGES = ("toe", "heel", "tip")
#: how a cell's force is spread over its footprint on the flank: "uniform" (the verdict's) or "punch"
#: (weighted by the distance to the edge to the power -1/2, the pressure's form near a sharp punch corner;
#: ``benchmarks/edge_band_convergence.py`` compares the two)
PROFILES = ("uniform", "punch")


def _sqrt_ramp_integral(x, q):
    """int_0^x max(s - q, 0) s^-1/2 ds for x >= 0 (arrays broadcast)."""
    lo = np.maximum(q, 0.0)
    f = lambda s: (2.0 / 3.0) * s * np.sqrt(s) - 2.0 * q * np.sqrt(s)  # noqa: E731
    return np.where(x > lo, f(np.maximum(x, lo)) - f(lo), 0.0)


def band_fractions(d, delta, a, b, profile: str = "uniform"):
    """(force, area): the fractions of cells' force and area within ``delta`` of an edge, for cells whose
    centres lie ``d`` from it and whose footprints spread over the distance as two uniform widths ``a``,
    ``b`` (a trapezoid; arrays broadcast).  The area fraction is the footprint's part between the edge and
    ``delta``; the force acts on the footprint's part on the flank (distance >= 0) only, uniformly
    (``profile`` "uniform") or weighted by distance^-1/2 ("punch").  A footprint wholly beyond the edge
    puts its whole force in the band."""
    if profile not in PROFILES:
        raise ValueError(f"profile = {profile!r}: valid are {', '.join(PROFILES)}")
    d = np.asarray(d, dtype=float)
    beyond = _trapezoid_cdf(-d, a, b)  # the footprint's part beyond the edge
    area = np.maximum(_trapezoid_cdf(delta - d, a, b) - beyond, 0.0)
    if profile == "uniform":
        on_flank = 1.0 - beyond
        ok = on_flank > 1e-12
        return np.where(ok, area / np.where(ok, on_flank, 1.0), 1.0), area
    # the trapezoid's density is a sum of ramps (as in face_load._trapezoid_cdf); its weighted integral
    a, b = np.maximum(a, b), np.minimum(a, b)
    b = np.maximum(b, 1e-3 * a + 1e-12)
    h, w = (a + b) / 2, (a - b) / 2

    def weighted(x):
        return (_sqrt_ramp_integral(x, d - h) - _sqrt_ramp_integral(x, d - w) - _sqrt_ramp_integral(x, d + w)
                + _sqrt_ramp_integral(x, d + h))

    top = np.maximum(d + h, 0.0)
    total = weighted(top)
    ok = total > 0
    return np.where(ok, weighted(np.clip(delta, 0.0, top)) / np.where(ok, total, 1.0), 1.0), area


@dataclass(frozen=True)
class EdgeLoad:
    """The edge band carrying the largest share of the mesh's load over the converged positions."""

    pressure_mpa: float  # the band's mean pressure (force over loaded area within delta of the edge)
    force_n: float  # the force within the band at that instant (one tooth pair's)
    share: float  # that force over the mesh's load at that instant
    band_mm: float  # delta
    member: str  # whose edge: "pinion" | "gear"
    edge: str  # "toe" | "heel" | "tip"
    position: int
    pinion_angle_rad: float
    tooth_pair: int


def _distances(geometry, member, pts):
    """{edge: distance (mm) of each cell point to that edge of ``member``} (nan where no point)."""
    z = np.asarray(sections.face_z(geometry, member, pts[..., 2]), dtype=float)
    w = float(sections.half_face(geometry, member))
    zc = np.where(np.isfinite(z), np.clip(z, -w, w), 0.0)
    tip = np.asarray(sections.section(geometry, member, zc).tip_radius, dtype=float)
    return {"toe": w + z, "heel": w - z, "tip": tip - np.hypot(pts[..., 0], pts[..., 1])}


class EdgeDistances:
    """The distances of each (position, pair)'s cell points to a member's toe, heel and tip (``_distances``) and
    their plane slopes over the pair's grid, each computed once for one result: :func:`surface_peaks` and
    :func:`edge_loads` read the same ones (the rating reads both)."""

    def __init__(self, result, geometry):
        self.result, self.geometry = result, geometry
        self._distances, self._slopes, self._grid = {}, {}, {}

    def points(self, j, k, member):
        return (self.result.gap.pinion_point if member == "pinion" else self.result.gap.gear_point)[j, k]

    def distances(self, j, k, member) -> dict:
        """{edge: distance (mm)} of pair k's cell points at position j (nan where no point)."""
        key = (j, k, member)
        if key not in self._distances:
            self._distances[key] = _distances(self.geometry, member, self.points(j, k, member))
        return self._distances[key]

    def slopes(self, j, k, member, edge) -> tuple:
        """(d/dx, d/dy) of that distance over the grid (``face_load._affine_slopes`` over the cells with a point)."""
        key = (j, k, member, edge)
        if key not in self._slopes:
            x, y, finite = self._fit_grid(j, k, member)
            self._slopes[key] = _affine_slopes(self.distances(j, k, member)[edge], x, y, finite)
        return self._slopes[key]

    def _fit_grid(self, j, k, member) -> tuple:
        """(x, y) of pair k's cells at position j, flat, and which of them have a point of ``member``: read once
        for the edges' slopes (each (position, pair, member) fits up to three)."""
        key = (j, k, member)
        if key not in self._grid:
            x, y = (c.reshape(-1) for c in self.result.cell_coordinates_mm(j, k))
            self._grid[key] = (x, y, np.isfinite(self.points(j, k, member)).all(axis=-1))
        return self._grid[key]


def _band_loads(result, geometry, delta: float, distances, profile: str, at_edge: bool = False):
    """Each (converged position, pair, member, edge) whose band of width ``delta`` carries load, as an EdgeLoad.
    ``at_edge``: each pair's share as if its loaded cell nearest the edge lay at the edge, where that cell lies
    within its own footprint's length of the edge and is the flank's nearest (:func:`edge_shares`)."""
    g = result.grid
    for j in np.flatnonzero(result.converged):
        total = float(np.nansum(result.pair_load_n[j]))
        if not total > 0:
            continue
        for k in range(result.pressure_mpa.shape[1]):
            p = result.pressure_mpa[j, k]
            loaded = (p > 0) & result.gap.in_flank[j, k]
            if not loaded.any():
                continue
            dx, dy = 2 * g.across_half_mm[j, k] / g.across_cells, 2 * g.along_half_mm[j, k] / g.along_cells
            area = float(result.cell_area_mm2[j, k])
            for member in MEMBERS:
                finite = np.isfinite(distances.points(j, k, member)).all(axis=-1)
                use = loaded & finite
                if not use.any():
                    continue
                for edge, d in distances.distances(j, k, member).items():
                    if not np.nanmin(d[use]) < delta + dx + dy:  # not within a cell of the band
                        continue
                    gx, gy = distances.slopes(j, k, member, edge)
                    fa, fb = abs(gx) * dx, abs(gy) * dy
                    du = d[use]
                    if at_edge:  # the cell passage's last instant before the nearest cell leaves the flank
                        near = float(np.min(du))
                        first = float(np.min(d[result.gap.in_flank[j, k] & finite]))  # the flank's cell nearest
                        if 0.0 < near <= fa + fb and near < first + 0.5 * (fa + fb):  # the pattern cut by the edge
                            du = du - near
                    share, in_band = band_fractions(du, delta, fa, fb, profile)
                    a = float(np.sum(in_band)) * area
                    if a <= 0:
                        continue
                    f = float(np.sum(p[use] * share)) * area
                    yield EdgeLoad(f / a, f, f / total, delta, member, edge, int(j), float(result.pinion_angle[j]),
                                   int(result.tooth_pairs[k]))


def _delta(geometry, band_mm):
    return BAND_MODULES * geometry.normal_module_mm if band_mm is None else float(band_mm)


def edge_loads(result, geometry, band_mm: float | None = None, by_edge: bool = False, distances=None,
               profile: str = "uniform"):
    """The edge band carrying the largest share of the mesh's load over the LTCA's converged positions, pairs,
    both members and their toe, heel and tip; None when no loaded cell comes within ``band_mm`` (default
    :data:`BAND_MODULES` m_n) of an edge.  ``by_edge``: each edge's own largest instead, as a tuple of
    EdgeLoad, largest share first (empty when none): a pair may run onto several edges (the tips of both
    members, a toe), each of which the edge rule judges.  ``distances``: this result's :class:`EdgeDistances`
    (None: made here).  ``profile``: how a cell's force spreads over its footprint on the flank
    (:func:`band_fractions`; the verdict's is "uniform")."""
    best = {}  # (member, edge) -> its EdgeLoad of largest share
    for e in _band_loads(result, geometry, _delta(geometry, band_mm), distances or EdgeDistances(result, geometry),
                         profile):
        now = best.get((e.member, e.edge))
        if now is None or e.share > now.share:
            best[e.member, e.edge] = e
    ranked = tuple(sorted(best.values(), key=lambda e: -e.share))
    if by_edge:
        return ranked
    return ranked[0] if ranked else None


def edge_shares(result, geometry, band_mm: float | None = None, distances=None, at_edge: bool = False) -> dict:
    """{(member, edge): (N,) the largest share of the mesh's load within the edge's band at each position of
    the LTCA (over its pairs; 0 where none, nan where the position did not converge)}, every edge that carries
    load within its band at some position: what :func:`edge_loads` takes the largest of, position by position
    (the rating refines the positions about its maxima, ``rating.analysis.refine_positions``).

    ``at_edge``: each pair's share with its band moved onto the pair's loaded cell nearest the edge, where that
    cell lies within its own footprint's length of the edge and no unloaded cell of the flank lies nearer (the
    pattern is cut by the edge, not ending before it): the share of that position's pressures at the
    last instant of the cell's passage, before its centre crosses the edge and it leaves the flank.  The
    contact grid follows the contact while the edge stays put, so as a pattern runs onto an edge its cells
    cross the edge one by one and the share at the positions is a sawtooth of one cell's passage: it rises
    while the nearest cell nears the edge (the band takes more of its footprint) and drops as it leaves (case 1's
    pareto design, docs/rating.md 6: 0.007 to 0.027 within 0.0015 rad, a cell of 0.50 mm against a band of
    0.30 mm).
    The largest share read depends on where the positions fall in the teeth; ``at_edge`` estimates each tooth's
    top from any of its positions (the rating's positions uncertainty of an edge share, ``verdict.limit_band``)."""
    ok = np.asarray(result.converged)
    out = {}
    for e in _band_loads(result, geometry, _delta(geometry, band_mm), distances or EdgeDistances(result, geometry),
                         "uniform", at_edge):
        a = out.setdefault((e.member, e.edge), np.where(ok, 0.0, np.nan))
        a[e.position] = max(a[e.position], e.share)
    return out


def surface_peaks(result, geometry, band_mm: float | None = None, distances=None) -> np.ndarray:
    """(N, P) the largest cell pressure (MPa) of each position and pair over the LTCA's loaded flank cells
    more than :data:`SURFACE_REACH` cell from an off-flank cell whose whole footprint lies farther than
    ``band_mm`` (default :data:`SURFACE_BAND_MODULES` m_n) from the toe, heel and tip of both members; nan
    where no such cell is loaded (or the position did not converge).  The verdict's local contact pressure
    (S_H) is read here: the pressure near a sharp edge, and most in a flank corner between two edges, is the
    edge's (the edge rule judges the load within :data:`BAND_MODULES` m_n), and read there it grows as the
    grid is refined (issue 57; docs/rating.md 5).  A cell's footprint (its distance to an edge over its
    widths, as :func:`edge_loads` spreads it), not a count of cells, bounds the reading: the band is the same
    length on every grid.  ``distances``: this result's :class:`EdgeDistances` (None: made here)."""
    from ..ltca.model import grid as grids

    distances = distances or EdgeDistances(result, geometry)

    delta = SURFACE_BAND_MODULES * geometry.normal_module_mm if band_mm is None else float(band_mm)
    g = result.grid
    p = result.pressure_mpa
    inner = grids.interior(p, result.gap.in_flank, g.across_cells, g.along_cells,
                           reach=SURFACE_REACH).reshape(p.shape)
    out = np.full(p.shape[:2], np.nan)
    for j in np.flatnonzero(result.converged):
        for k in range(p.shape[1]):
            keep = inner[j, k] & (p[j, k] > 0)
            if not keep.any():
                continue
            dx, dy = 2 * g.across_half_mm[j, k] / g.across_cells, 2 * g.along_half_mm[j, k] / g.along_cells
            for member in MEMBERS:
                finite = np.isfinite(distances.points(j, k, member)).all(axis=-1)
                for edge, d in distances.distances(j, k, member).items():
                    if int(finite.sum()) >= 3:
                        gx, gy = distances.slopes(j, k, member, edge)
                        d = d - 0.5 * (abs(gx) * dx + abs(gy) * dy)  # the footprint's nearest point
                    keep &= ~(d < delta)
            if keep.any():
                out[j, k] = float(p[j, k][keep].max())
    return out

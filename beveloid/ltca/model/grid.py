"""The contact grid of each (position, tooth pair), sized from the contact itself.

Each pair's grid is a tensor grid of ``across x along`` flat cells in its tangent plane, its axes
along the principal directions of the relative curvature.  Its half-extents are
:data:`EXTENT_ACROSS` times the local Hertz semi-minor axis b and :data:`EXTENT_ALONG` times the
semi-major axis a (capped by the flank diagonal), for the pair's curvature and load, so that a
cell is a fixed fraction of the Hertz semi-axes (2 EXTENT / cells: 0.27 b across and 0.18 a along
with the default 11 x 17 cells) whatever the design.  The cell counts are the same for every pair
and position; their size is not.
"""
from __future__ import annotations

import functools
import math
import typing

import numpy as np

from ..mechanics import checks, hertz

EXTENT_ACROSS = 1.5  #: grid half-extent across the contact line / Hertz semi-minor axis b
EXTENT_ALONG = 1.5  #: grid half-extent along the contact line / Hertz semi-major axis a
GROWTH = 1.5  #: a grid whose loaded flank cells reach its outermost rows grows by this factor
MAX_GROWTHS = 3
LOAD_FLOOR = 0.02  #: a pair is sized for at least this share of the full load
PATCH_MARGIN = 1.25  #: the result grid's along extent / the first pass's loaded half-length (plus a cell)
INTERIOR_REACH = 2  #: loaded cells within this many cells of an off-flank cell are edge contact
#: a patch of edge cells only (a flank corner, a narrow strip at a face end) grows its grid when it carries
#: this share of its position's load (the edge rule's limit, docs/rating.md 6); a lighter one is left as it is
CORNER_SHARE = 0.02
#: an edge line of a patch whose interior the grid holds grows its grid where the cells the grid's outermost row
#: cuts (each with its inward neighbour loaded) carry this share of the position's load: an edge line the grid
#: clipped, not a sliver's end (random design R31-4 at 300 N m, default grid: a leaving pair's tip-edge line
#: left its grid across, its 2 680 N on 8.5 mm of face against 13.4 mm at the angle beside it, K_Hbeta 2.18 at one instant against
#: 1.85-1.92 beside it and on the 15x25 / 21x35 grids; docs/validation.md 10.1)
EDGE_LINE_SHARE = 0.01


class PairGrid(typing.NamedTuple):
    """Cell counts (shared) and half-extents (mm) of the grid of every (position, pair)."""

    across_cells: int
    along_cells: int
    across_half_mm: np.ndarray  # (N, P)
    along_half_mm: np.ndarray  # (N, P)

    @property
    def cells(self) -> int:
        return self.across_cells * self.along_cells

    def unit_centres(self):
        """Cell centres of a grid of half-extent 1 (across (nx,), along (ny,))."""
        return centres(1.0, self.across_cells), centres(1.0, self.along_cells)

    def cell_area_mm2(self) -> np.ndarray:
        """(N, P) area of one cell of each grid."""
        return 4.0 * self.across_half_mm * self.along_half_mm / self.cells

    def coarsened(self) -> "PairGrid":
        """The same extents with about 1.6 times fewer cells each way (odd counts, at least 5)."""
        return self._replace(across_cells=coarser(self.across_cells), along_cells=coarser(self.along_cells))


def coarser(n: int) -> int:
    m = max(5, int(round(n / 1.6)))
    return m + 1 - m % 2 if n % 2 else m


def resample_along(a, n):
    """a (..., m) given at the m along-cell centres of a grid, linearly interpolated at the n along-cell
    centres of a grid of the same extent (n <= m: the centres lie inside the first grid's)."""
    m = a.shape[-1]
    w = np.zeros((n, m))  # the interpolation weights, one row per new centre
    t = (centres(1.0, n) + 1.0) * 0.5 * m - 0.5  # the new centres in old cell indices
    lo = np.clip(np.floor(t).astype(int), 0, m - 2)
    f = t - lo
    w[np.arange(n), lo] = 1.0 - f
    w[np.arange(n), lo + 1] = f
    return a @ w.T


def edges(half, n):
    return np.linspace(-half, half, n + 1)


def centres(half, n):
    """The n cell centres of a grid of half-extent ``half`` (a number): those of half-extent 1 made once (read-only)."""
    if half == 1.0:
        return _unit_centres(int(n))
    e = edges(half, n)
    return 0.5 * (e[1:] + e[:-1])


@functools.lru_cache(maxsize=64)
def _unit_centres(n):
    e = edges(1.0, n)
    out = 0.5 * (e[1:] + e[:-1])
    out.flags.writeable = False
    return out


def hertz_semi_axes(k_across, k_along, load_n, e_star_mpa, line_length_mm):
    """(b across, a along) Hertz semi-axes (mm) of gaps 1/2 (k_across x^2 + k_along y^2) under
    ``load_n``, elementwise; a line contact (a beyond ``line_length_mm``, or k_along <= 0) gets the
    2-D half-width with the load spread over ``line_length_mm`` and a = inf."""
    k_across, k_along, load = np.broadcast_arrays(np.asarray(k_across, float), np.asarray(k_along, float),
                                                  np.asarray(load_n, float))
    b = np.full(k_across.size, np.nan)
    a = np.full(k_across.size, np.nan)
    e_star = checks.positive("e_star_mpa", e_star_mpa)
    for i, (ka, kl, f) in enumerate(zip(k_across.ravel().tolist(), k_along.ravel().tolist(), load.ravel().tolist())):
        if not (math.isfinite(ka) and ka > 0 and math.isfinite(f) and f > 0):
            continue
        if math.isfinite(kl) and kl > 0 and ka / kl < 1e8:
            major, minor = hertz.semi_axes_mm(kl / 2, ka / 2, f, e_star)  # hertz_point_contact's, unchecked
            if major < line_length_mm:
                b[i], a[i] = minor, major
                continue
        line = hertz.hertz_line_contact(1.0 / ka, f / line_length_mm, e_star)
        b[i], a[i] = line.half_width_mm, math.inf
    b, a = b.reshape(k_across.shape), a.reshape(k_across.shape)
    return b, a


def hertz_peak_mpa(k_across, k_along, load_n, e_star_mpa, line_length_mm):
    """The Hertz peak pressure (MPa) of :func:`hertz_semi_axes`' contact: 3F/(2 pi a b), or
    2 q/(pi b) with q = F / line_length_mm for a line contact; nan where there is no contact."""
    b, a = hertz_semi_axes(k_across, k_along, load_n, e_star_mpa, line_length_mm)
    load = np.broadcast_to(np.asarray(load_n, float), b.shape)
    with np.errstate(all="ignore"):
        return np.where(np.isfinite(a), 3 * load / (2 * np.pi * a * b), 2 * load / line_length_mm / (np.pi * b))


def sized(cells, b, a, max_along_mm, fallback) -> PairGrid:
    """A grid of ``cells`` (across, along) whose extents are EXTENT times the semi-axes (b, a)
    (N, P); where they are unknown (no load, no curvature), the extents of ``fallback`` (N, P, 2)."""
    X = np.where(np.isfinite(b), EXTENT_ACROSS * b, fallback[..., 0])
    Y = np.minimum(np.where(np.isnan(a), fallback[..., 1], EXTENT_ALONG * a), max_along_mm)
    return PairGrid(int(cells[0]), int(cells[1]), X, Y)


def interior(p, in_flank, nx, ny, reach=INTERIOR_REACH):
    """Loaded cells (..., nx, ny) farther than ``reach`` cells (8-neighbourhood) from any off-flank
    cell: cells nearer a blank boundary carry edge contact, which the blank (not the grid) bounds."""
    q = (p > 0).reshape(p.shape[:-1] + (nx, ny))
    inner = in_flank.reshape(q.shape).copy()
    pad = np.ones(inner.shape[:-2] + (nx + 2, ny + 2), dtype=bool)  # a ring of on-flank cells about the grid
    for _ in range(reach):
        pad[..., 1:-1, 1:-1] = inner
        for di in (-1, 0, 1):
            for dj in (-1, 0, 1):
                inner &= pad[..., 1 + di:1 + di + nx, 1 + dj:1 + dj + ny]
    return q & inner


def reaches_edge(p, in_flank, nx, ny, load_share=None):
    """(N, P, 2): the loaded patch runs into the outermost (across, along) rows of each grid: an interior
    loaded cell there; or, for a patch with no interior cell at all carrying at least :data:`CORNER_SHARE`
    of its position's load (``load_share`` (N, P); None: any), a loaded flank cell there whose inward
    neighbour is loaded too, or any loaded cell there if the patch lies in the two outermost rows only
    (a strip one cell wide that the placement held at the grid's edge).  Such a patch lies in a corner of the flank, cut by the tip and an end (every
    cell within :data:`INTERIOR_REACH` of the blank), and the grid, not the blank, cut it unseen (issue 57);
    a lone loaded cell at the grid's edge, the end of an edge line's sliver, does not grow the grid.  The edge
    line of a patch whose interior is held inside the grid grows it only where its cells in the outermost row
    with a loaded inward neighbour carry :data:`EDGE_LINE_SHARE` of the position's load (``load_share`` given):
    a loaded edge line the grid clipped (growing every such line cost 32 % of the tolerance box's analysis
    time: ``python benchmarks/ltca_growth_rules.py``, docs/loaded_contact.md 8.1)."""
    shape = p.shape[:-1] + (nx, ny)
    q = (p > 0).reshape(shape) & in_flank.reshape(shape)
    inner = interior(p, in_flank, nx, ny)
    corner = ~inner.any(axis=(-1, -2))
    if load_share is not None:
        corner &= load_share >= CORNER_SHARE
    corner = corner[..., None, None]
    # a patch whose every loaded cell lies in the two outermost rows (a strip one cell wide held at the grid's
    # edge by a placement off the patch) is cut there too
    strip_across = q.any(axis=(-1, -2)) & ~q[..., 1:-1, :].any(axis=(-1, -2))
    strip_along = q.any(axis=(-1, -2)) & ~q[..., :, 1:-1].any(axis=(-1, -2))
    # a loaded flank cell in an outermost row whose inward neighbour is loaded too: the patch crosses that row
    cut = (q[..., [0, -1], :] & q[..., [1, -2], :], q[..., :, [0, -1]] & q[..., :, [1, -2]])
    heavy = [np.zeros(q.shape[:-2] + (1, 1), dtype=bool)] * 2
    if load_share is not None:  # the share of the position's load those cells carry (a pair's cells: one area)
        pr = np.where(q, p.reshape(shape), 0.0)
        total = pr.sum(axis=(-1, -2))
        own = np.where(total > 0, load_share, 0.0) / np.where(total > 0, total, 1.0)
        heavy = [((np.where(c, edge, 0.0).sum(axis=(-1, -2)) * own) >= EDGE_LINE_SHARE)[..., None, None]
                 for c, edge in zip(cut, (pr[..., [0, -1], :], pr[..., :, [0, -1]]))]
    across = ((corner | heavy[0]) & cut[0]) | (corner & strip_across[..., None, None]) | inner[..., [0, -1], :]
    along = ((corner | heavy[1]) & cut[1]) | (corner & strip_along[..., None, None]) | inner[..., :, [0, -1]]
    return np.stack([across.any(axis=(-1, -2)), along.any(axis=(-1, -2))], axis=-1)


def loaded_across_centres_mm(solution):
    """(N, P, along cells) the across coordinate (mm, the pair's tangent-plane frame, as the column
    offsets) of each along-column's pressure centroid; nan for a column without load."""
    g = solution.grid
    nx, ny = g.across_cells, g.along_cells
    p = solution.pressure_mpa.reshape(solution.pressure_mpa.shape[:2] + (nx, ny))
    x = (centres(1.0, nx)[None, None, :, None] * g.across_half_mm[..., None, None]
         + solution.gap.across_shift_mm[:, :, None, :])
    w = p.sum(axis=-2)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(w > 0, (p * x).sum(axis=-2) / w, np.nan)


#: the loaded columns at each end of a patch whose centroids' straight line continues it beyond them
LINE_END_COLUMNS = 3


def continued_line(a, old_half, new_half):
    """a (N, P, n) given at the n along-cell centres of grids of half-extents ``old_half`` (N, P) along
    (nan where unknown), at the centres of grids of the same cell count and half-extents ``new_half``:
    linear between the known values, and beyond the first and last known ones the straight line fitted
    through the :data:`LINE_END_COLUMNS` known values at that end (a contact line is straight to first
    order); a row without a known value is 0."""
    n = a.shape[-1]
    u = centres(1.0, n)
    out = np.zeros_like(a)
    for idx in np.ndindex(a.shape[:-1]):
        ok = np.isfinite(a[idx])
        if not ok.any():
            continue
        y, v, t = u[ok] * old_half[idx], a[idx][ok], u * new_half[idx]
        out[idx] = np.interp(t, y, v)
        if y.size < 2:
            continue
        m = min(LINE_END_COLUMNS, y.size)
        for side, beyond in ((slice(0, m), t < y[0]), (slice(y.size - m, y.size), t > y[-1])):
            if beyond.any():  # the least-squares line through the end's values
                ys, vs = y[side], v[side]
                dy = ys - ys.mean()
                slope = float(dy @ (vs - vs.mean()) / (dy @ dy))
                out[idx][beyond] = vs.mean() + slope * (t[beyond] - ys.mean())
    return out


def loaded_along_mm(solution):
    """(N, P) half-length along the line of each pair's loaded cells, plus one cell (nan if unloaded)."""
    g = solution.grid
    nx, ny = g.across_cells, g.along_cells
    q = (solution.pressure_mpa > 0).reshape(solution.pressure_mpa.shape[:2] + (nx, ny)).any(axis=-2)
    y = np.abs(centres(1.0, ny))[None, None, :] * g.along_half_mm[..., None]
    with np.errstate(invalid="ignore"):
        half = np.where(q, y, -np.inf).max(axis=-1) + 2 * g.along_half_mm / ny
    return np.where(q.any(axis=-1), half, np.nan)

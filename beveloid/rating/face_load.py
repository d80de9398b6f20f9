"""The face load factor from the loaded contact (docs/rating.md 2.3): the line load along each member's
face, from the LTCA's pressure on its contact grids, and ISO 6336-1's K_Hbeta = w_max / w_m.

At each converged position the normal force of every loaded cell of every tooth pair is spread over
the face coordinate of the member (``sections.face_z`` of the cell's point in the member frame) by
the cell's own footprint: a cell of widths (dx, dy) on its grid, whose face coordinate varies as
z = z0 + s_x x + s_y y (least squares over the pair's cells), covers the face interval of the sum of
two uniform spreads of widths |s_x| dx and |s_y| dy (a trapezoid).  This is the exact face marginal
of the cell-wise constant pressure field, so a uniform line load gives w = F/L, a Hertz ellipse its
parabola.  Summed over the pairs this is the mesh's line load w_j(z) (N/mm of face); with the mean
w_m,j = F_j / b over the common face width b (the b of sigma_H0 and sigma_F0),

    K_Hbeta = max_j max_z w̄_j(z) / w_m,j      (ISO 6336-1, 7.1: peak over mean line load)

over the converged positions j: the instant and place of the largest line load, w̄ the line load's mean over
:data:`WINDOW_MODULES` normal modules of face centred on z.  The standard does not say over what length a
"load per unit face width" is taken; at the cells' own resolution the peak grows without bound as the grid is
refined where a pair's load runs into a corner of its contact (a sharp edge's singular pressure at the end of a
short contact line), while its mean over half a module converges and leaves a smooth distribution as it is
(docs/rating.md 2.3).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..tooth import sections

__all__ = ["FaceLoad", "WINDOW_MODULES", "face_load", "line_load_on_face", "line_loads", "window_mean"]

#: face bins per smallest cell footprint (the peak of the binned marginal is then within ~1 % of its
#: continuous peak for a Hertz parabola 10 cells long)
BINS_PER_FOOTPRINT = 4
MAX_BINS = 20000
#: the loaded length is where the line load exceeds this share of its peak
SUPPORT_SHARE = 0.01
#: a later position takes the peak from an earlier one only when its ratio is larger by more than this
#: (relative): positions whose peaks are equal but for round-off (case 1's pinion at 1500 N m: two positions
#: within 1e-12, 0.8 mm apart on the face) report the first, on any machine and backend
TIE_RELATIVE = 1e-9
#: the length of face (in normal modules) over which the line load is averaged before its peak is read
#: (:func:`window_mean`): well under the tooth's thickness at its pitch line (~1.6 m_n), over which a tooth spreads
#: a concentrated load anyway, and short against a contact ellipse (a parabola 4 m_n long loses 0.5 % of its peak) or a
#: linear distribution over the face (K_Hbeta 1.5 over b = 10 m_n reads 1.475)
WINDOW_MODULES = 0.5


@dataclass(frozen=True)
class FaceLoad:
    """The largest line load over the face and the cycle, relative to the mean (one member)."""

    K_H_beta: float | None  # None: no converged loaded position
    peak_line_load_n_per_mm: float | None
    mean_line_load_n_per_mm: float | None
    face_z_mm: float | None  # where the peak is (face coordinate, toe < 0 < heel)
    position: int | None  # the LTCA position index of the peak
    loaded_length_mm: float | None  # extent of the line load (> 1 % of its peak) at that position


def _trapezoid_cdf(t, a, b):
    """P(X + Y <= t) for X, Y uniform of widths a, b (>= 0) centred on 0 (arrays broadcast)."""
    a, b = np.maximum(a, b), np.minimum(a, b)
    b = np.maximum(b, 1e-3 * a + 1e-12)  # a thousandth of a cell's smear: exact enough, no cancellation
    ramp2 = lambda s: np.maximum(s, 0.0) ** 2  # noqa: E731
    h, d = (a + b) / 2, (a - b) / 2
    t = np.clip(t, -h, h)  # 0 and 1 outside the footprint, without the cancellation of large squares
    return (ramp2(t + h) - ramp2(t + d) - ramp2(t - d) + ramp2(t - h)) / (2 * a * b)


def _affine_slopes(v, x, y, fit):
    """(dv/dx, dv/dy) of a quantity v over a pair's grid (the face coordinate here, the distance to an
    edge in ``edge``): least squares over every cell whose point exists, ``fit`` (the whole grid, not
    only the loaded or in-flank cells: a pair with one or two loaded cells, or in-flank cells along one
    grid line, leaves a fit on those underdetermined, issue 57)."""
    A = np.stack([np.ones(int(fit.sum())), x[fit], y[fit]], axis=-1)
    (_, sx, sy), _, rank, _ = np.linalg.lstsq(A, v[fit], rcond=None)
    if rank < 3:
        raise ValueError(f"a quantity over a contact grid has no plane fit ({int(fit.sum())} cells with a point): "
                         "the footprint of its cells is undefined")
    return sx, sy


def _cell_footprints(result, geometry, member, j, k):
    """(face z of each loaded cell, its force N, trapezoid widths a, b) of pair k at position j."""
    p = result.pressure_mpa[j, k]
    loaded = p > 0
    pts = (result.gap.pinion_point if member == "pinion" else result.gap.gear_point)[j, k]
    ok = np.isfinite(pts).all(axis=-1) & result.gap.in_flank[j, k]
    use = loaded & ok
    if not use.any():
        return None
    z = np.asarray(sections.face_z(geometry, member, pts[..., 2]), dtype=float)
    x, y = (c.reshape(-1) for c in result.cell_coordinates_mm(j, k))
    sx, sy = _affine_slopes(z, x, y, np.isfinite(pts).all(axis=-1))
    g = result.grid
    dx, dy = 2 * g.across_half_mm[j, k] / g.across_cells, 2 * g.along_half_mm[j, k] / g.along_cells
    force = p[use] * result.cell_area_mm2[j, k]
    return z[use], force, abs(sx) * dx, abs(sy) * dy


def line_load_on_face(result, geometry, member, j):
    """(bin edges (n+1,) in face mm, line load (n,) N/mm) of the mesh at position j on ``member``'s face,
    or None when no pair carries load there."""
    parts = [f for k in range(result.pressure_mpa.shape[1]) if (f := _cell_footprints(result, geometry, member, j, k))]
    if not parts:
        return None
    z, force = np.concatenate([p[0] for p in parts]), np.concatenate([p[1] for p in parts])
    a = np.concatenate([np.full(len(p[0]), p[2]) for p in parts])
    b = np.concatenate([np.full(len(p[0]), p[3]) for p in parts])
    reach = 0.51 * (a + b) + 1e-9  # the footprint, and the floor _trapezoid_cdf puts under its smaller width
    lo, hi = float(np.min(z - reach)), float(np.max(z + reach))
    width = max(float(np.min(a + b)), 1e-6 * (hi - lo + 1e-3))
    n = int(min(MAX_BINS, max(50, math.ceil((hi - lo) / width * BINS_PER_FOOTPRINT))))
    edges = np.linspace(lo - 1e-9, hi + 1e-9, n + 1)
    cdf = _trapezoid_cdf(edges[None, :] - z[:, None], a[:, None], b[:, None])
    w = (force[:, None] * np.diff(cdf, axis=1)).sum(axis=0) / np.diff(edges)
    return edges, w


def window_mean(edges, w, length_mm: float) -> np.ndarray:
    """(n,) the mean of the binned line load ``w`` (bin ``edges``) over a window of ``length_mm`` centred on each
    bin's centre: exact for the binned load, whose integral is piecewise linear (zero before the first edge,
    the whole load after the last)."""
    cumulative = np.concatenate([[0.0], np.cumsum(w * np.diff(edges))])
    centres = 0.5 * (edges[1:] + edges[:-1])
    return (np.interp(centres + 0.5 * length_mm, edges, cumulative)
            - np.interp(centres - 0.5 * length_mm, edges, cumulative)) / length_mm


def line_loads(result, geometry, member) -> dict:
    """{position j: :func:`line_load_on_face` (or None)} of every converged position whose pairs carry load: what
    :func:`face_load` reads, computed once where several of its calls read the same result (the rating's
    K_Hbeta and its positions check: all positions and each half)."""
    take = np.flatnonzero(result.converged)
    return {int(j): line_load_on_face(result, geometry, member, j) for j in take
            if float(np.nansum(result.pair_load_n[j])) > 0}


def face_load(result, geometry, member, face_width_mm, positions=None, lines=None) -> FaceLoad:
    """K_Hbeta of ``member`` from an ``LTCAResult`` (module docstring); b = ``face_width_mm``; ``positions``:
    the position indices to take (None: all; the rating's positions check takes every other one); ``lines``:
    :func:`line_loads` of this result and member (None: computed here)."""
    best = None
    window = WINDOW_MODULES * geometry.normal_module_mm
    take = result.converged.copy()
    if positions is not None:
        take &= np.isin(np.arange(take.size), positions)
    for j in np.flatnonzero(take):
        total = float(np.nansum(result.pair_load_n[j]))
        if total <= 0:
            continue
        line = line_load_on_face(result, geometry, member, j) if lines is None else lines[int(j)]
        if line is None:
            continue
        edges, w = line
        smooth = window_mean(edges, w, window)
        i = int(np.argmax(smooth))
        mean = total / face_width_mm
        ratio = float(smooth[i]) / mean
        if best is None or ratio > best[0] * (1.0 + TIE_RELATIVE):
            centres = 0.5 * (edges[1:] + edges[:-1])
            loaded = centres[w > SUPPORT_SHARE * float(np.max(w))]
            length = float(loaded.max() - loaded.min() + (edges[1] - edges[0]))
            best = (ratio, float(smooth[i]), mean, float(centres[i]), int(j), length)
    if best is None:
        return FaceLoad(None, None, None, None, None, None)
    return FaceLoad(*best)

"""The LTCA's loaded patches at the checked position as contact strips on each member's sector
(``beveloid.fe.sizes``): where fe-check's mesh is refined.

Per loaded tooth pair k of the LTCA: its loaded cells (pressure > 0) at the position, on each
member's flank (the LTCA's cell points, member frame, tooth 0) turned onto the sector's tooth of
that pair (pinion tooth -s1 k, gear tooth s2 k, as :func:`beveloid.fecheck.pair_model.sector_teeth`).
The strip's centre line: per along-column of the LTCA's grid the pressure-weighted centroid of its
loaded cells.  Its half-width: (1 + ``STRIP_MARGIN``) x the larger of the patch's short semi-axis
b (``LTCAResult.patch_semi_axes_mm``, sqrt(5 <x^2>) of the pressure: exact for a Hertz ellipse)
and the widest column's loaded half-extent (an edge contact is not an ellipse); its target size
b x ``SIZE_PER_SEMI_AXIS`` (b / 3: a Hertz contact is resolved to about 1 % by 3-4 quadratic
elements per semi-axis, docs/validation.md section 11) or the size asked for.
"""
from __future__ import annotations

import math

import numpy as np

from ..fe.sizes import MAX_STRIP_ELEMENTS, ContactStrip, ContactStrips

__all__ = ["SIZE_PER_SEMI_AXIS", "STRIP_MARGIN", "ltca_strips"]

SIZE_PER_SEMI_AXIS = 1.0 / 3.0
#: the refined tube reaches this fraction of the half-width beyond the LTCA's patch (the FE's patch
#: is not the LTCA's: its loads differ by up to ~40 % on the side pairs, its widths by the root)
STRIP_MARGIN = 0.5


def _rotate_z(points, angle):
    c, s = math.cos(angle), math.sin(angle)
    return np.stack([c * points[:, 0] - s * points[:, 1], s * points[:, 0] + c * points[:, 1], points[:, 2]], axis=1)


def _centre_line(points, p, across):
    """(centre line (m, 3), half-extent across (mm)) of one member's loaded cells: per along-column."""
    line, half = [], 0.0
    for iy in range(p.shape[1]):
        on = (p[:, iy] > 0) & np.isfinite(points[:, iy]).all(axis=1)
        if not on.any():
            continue
        w = p[on, iy] / p[on, iy].sum()
        line.append(w @ points[on, iy])
        x = across[on, iy]
        half = max(half, 0.5 * (x.max() - x.min()))
    return np.array(line), half


def ltca_strips(result, j, geom, teeth, size_mm=None, max_elements=MAX_STRIP_ELEMENTS):
    """({"pinion": ContactStrips, "gear": ContactStrips}, [per strip {"tooth_pair", "semi_axes_mm",
    "half_width_mm", "size_mm"}]) of the LTCA's loaded pairs at position ``j``.

    ``teeth``: per LTCA pair (``result.tooth_pairs`` order) the sector teeth (pinion, gear) or None
    outside the sectors; ``size_mm``: the target size (None: b / 3 per pair)."""
    axes = result.patch_semi_axes_mm()[j]
    nx, ny = result.grid.across_cells, result.grid.along_cells
    pitch = {"pinion": 2 * math.pi / geom.pinion.teeth, "gear": 2 * math.pi / geom.gear.teeth}
    found = {"pinion": [], "gear": []}
    about = []
    for k, pair_teeth in enumerate(teeth):
        p = np.asarray(result.pressure_mpa[j, k], dtype=float).reshape(nx, ny)
        if pair_teeth is None or not np.isfinite(axes[k]).all() or not (p > 0).any():
            continue
        across, _ = result.cell_coordinates_mm(j, k)
        b, a = float(axes[k, 0]), float(axes[k, 1])
        size = float(size_mm) if size_mm is not None else SIZE_PER_SEMI_AXIS * b
        cell_half = result.grid.across_half_mm[j, k] / nx
        entry = {"tooth_pair": int(result.tooth_pairs[k]), "semi_axes_mm": [b, a], "size_mm": size}
        widths = []
        for member, tooth, pts in (("pinion", pair_teeth[0], result.gap.pinion_point[j, k]),
                                   ("gear", pair_teeth[1], result.gap.gear_point[j, k])):
            line, half = _centre_line(np.asarray(pts, dtype=float).reshape(nx, ny, 3), p, across)
            width = (1.0 + STRIP_MARGIN) * max(b, half + cell_half)
            widths.append(width)
            found[member].append(ContactStrip(_rotate_z(line, tooth * pitch[member]), width, size))
        entry["half_width_mm"] = max(widths)
        about.append(entry)
    return {m: ContactStrips(tuple(s), max_elements) for m, s in found.items()}, about

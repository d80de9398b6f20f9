"""How far a modified flank departs from its body (:mod:`beveloid.tooth.body`): measured, not declared.

:func:`flank_departure` compares the two flanks at the body's FE load grid points, along the body's
normals.  Bending compliance goes as 1/s^3 of the tooth thickness s, so a departure delta of one
flank changes it by about 3 delta / s where it lies; over the flank that is about 3 rms(delta) /
mean(s).  Above :data:`DEPARTURE_LIMIT` (1 %: a ~3 % change, the size of the FE tooth's own
discretisation error) the loaded analysis says so in its notes.  A tip or end relief is large only
where the tooth is loaded little and barely moves that measure; a flank turned or thinned all over
moves it fully.
"""
from __future__ import annotations

import typing

import numpy as np

from ..names import FLANKS
from .body import is_body
from .profile import flank_at_radius

__all__ = ["DEPARTURE_LIMIT", "Departure", "flank_departure", "flank_thickness_mm"]

#: a flank departing from its body by more than this fraction of the local tooth thickness is noted
DEPARTURE_LIMIT = 0.01


def flank_thickness_mm(points) -> np.ndarray:
    """(2, ...) the tooth's thickness at grid points (2 flanks, ..., 3): each point's distance to the
    nearest grid point of the other flank (an upper bound on a coarse grid)."""
    from scipy.spatial import cKDTree

    p = np.asarray(points, dtype=float)
    flat = p.reshape(2, -1, 3)
    return np.stack([cKDTree(flat[1 - f]).query(flat[f])[0] for f in range(2)]).reshape(p.shape[:-1])


class Departure(typing.NamedTuple):
    """How far a member's modified flank lies from its body at the body's grid points."""

    max_um: float  # the largest |normal distance| over both flanks' grid points
    rms_over_thickness: float  # the flank's rms distance over its mean thickness (the larger flank's)
    flank: str  # the flank of the largest distance
    z_mm: float  # and where it is

    def note(self, member: str) -> str | None:
        """One line when the departure exceeds :data:`DEPARTURE_LIMIT`, else None."""
        if not self.rms_over_thickness > DEPARTURE_LIMIT:
            return None
        return (f"{member}: the flanks depart from the FE tooth's body (the unmodified rack's tooth) by"
                f" {100 * self.rms_over_thickness:.1f} % of the tooth thickness (rms; up to {self.max_um:.1f} um on the"
                f" {self.flank} flank at z = {self.z_mm:.2f} mm): its bending compliance and root stress are the body's,"
                f" off by about {300 * self.rms_over_thickness:.0f} %")


def flank_departure(pair, member: str, points, normals) -> Departure:
    """The member's flank against its body: the distance along the body's outward normals (2, ns, nz, 3)
    from the body's grid points (2, ns, nz, 3) (flanks left, right) to the member's flank point of the
    same axial position and radius."""
    geometry = getattr(pair, "geometry", pair)
    points, normals = np.asarray(points, dtype=float), np.asarray(normals, dtype=float)
    if is_body(geometry, member):
        return Departure(0.0, 0.0, FLANKS[0], float(points[0, 0, 0, 2]))
    m = geometry.member(member)
    thick = flank_thickness_mm(points)
    rms, largest, where = 0.0, 0.0, (FLANKS[0], float(points[0, 0, 0, 2]))
    for f, flank in enumerate(FLANKS):
        z = points[f, ..., 2]
        radius = np.hypot(points[f, ..., 0], points[f, ..., 1])
        with np.errstate(all="ignore"):
            modified = flank_at_radius(geometry, member, flank, z, radius, l0=m.tip_height_mm + m.cutter_addendum_mm,
                                       strict=False)[0]
            distance = np.abs(np.einsum("...k,...k->...", modified - points[f], normals[f]))
        found = np.isfinite(distance)
        if not found.any():  # no point of the member's flank at the body's radii
            continue
        rms = max(rms, float(np.sqrt(np.mean(distance[found] ** 2)) / np.mean(thick[f][found])))
        k = np.unravel_index(int(np.nanargmax(distance)), distance.shape)
        if distance[k] > largest:
            largest, where = float(distance[k]), (flank, float(z[k]))
    return Departure(1e3 * largest, rms, *where)

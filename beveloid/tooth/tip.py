"""Tip thickness along the face, per member (definitions: derivations/tooth_sections.py).

The transverse tip thickness at face coordinate z is the arc thickness of the tooth at the
tip-cone radius r_a(z) in the transverse section z: r_a theta(r_a), theta the tooth's angular
thickness between the two flanks' involutes there.  Negative where the flanks cross below the tip
cone: the tooth is **pointed** there, its real tip is where they cross (``pointed_tip_radius``).
Crowning is not included (it thins the tip by a few um).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq, minimize_scalar

from . import sections


@dataclass(frozen=True)
class TipThickness:
    member: str
    toe_mm: float
    middle_mm: float
    heel_mm: float
    min_mm: float
    min_at_mm: float  # face coordinate of the thinnest tip
    pointed_from_mm: float | None  # face range where the tip thickness is <= 0 (None: not pointed)
    pointed_to_mm: float | None
    #: where pointed: the radius at which the flanks meet in the thinnest section, and how far below the tip cone
    pointed_tip_radius_mm: float | None
    pointed_tip_below_mm: float | None

    @property
    def pointed(self) -> bool:
        return self.pointed_from_mm is not None

    def to_json_dict(self):
        return {"toe": self.toe_mm, "middle": self.middle_mm, "heel": self.heel_mm}

    def message(self):
        return (f"pointed: {self.member} teeth from z = {self.pointed_from_mm:.3f} to {self.pointed_to_mm:.3f} mm"
                f" (face coordinate, toe at -W/2): the transverse tip thickness reaches {self.min_mm:.4f} mm at"
                f" z = {self.min_at_mm:.3f} mm, where the flanks meet at radius {self.pointed_tip_radius_mm:.4f} mm,"
                f" {self.pointed_tip_below_mm:.4f} mm below the tip cone")


def thickness(geometry, member: str, z_face):
    """Transverse arc thickness (mm) at the tip-cone radius of the section(s) z_face."""
    return sections.section(geometry, member, z_face).tip_arc_thickness


def pointed_tip_radius(geometry, member: str, z_face: float) -> float:
    """Radius (mm) where the two flanks meet in the section z_face (the tooth's angular thickness is 0)."""
    s = sections.section(geometry, member, z_face)
    lo = max(float(s.base_radius_left), float(s.base_radius_right)) * (1 + 1e-12)
    f = lambda R: float(sections.thickness_at_radius(geometry, member, z_face, R).thickness_angle)  # noqa: E731
    return brentq(f, lo, float(s.tip_radius), xtol=1e-12, rtol=4 * np.finfo(float).eps)


def tip_thickness(geometry, member: str, n: int = 101) -> TipThickness:
    w = sections.half_face(geometry, member)
    f = lambda zf: float(thickness(geometry, member, zf))  # noqa: E731
    grid = sections.face_grid(geometry, member, n)
    values = thickness(geometry, member, grid)
    k = int(np.argmin(values))
    lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, n - 1)]
    best = minimize_scalar(f, bounds=(lo, hi), method="bounded", options={"xatol": 1e-10})
    cands = [(float(values[k]), float(grid[k])), (float(best.fun), float(best.x))]
    min_mm, min_at = min(cands)
    toe, mid, heel = (float(v) for v in thickness(geometry, member, np.array([-w, 0.0, w])))
    ranges = sections.positive_ranges(lambda zf: -f(zf), grid)
    if not ranges:
        return TipThickness(member, toe, mid, heel, min_mm, min_at, None, None, None, None)
    radius = pointed_tip_radius(geometry, member, min_at)
    tip = float(sections.section(geometry, member, min_at).tip_radius)
    return TipThickness(member, toe, mid, heel, min_mm, min_at, ranges[0][0], ranges[-1][1], radius, tip - radius)


def tip_thicknesses(geometry) -> dict:
    return {m: tip_thickness(geometry, m) for m in sections.MEMBERS}

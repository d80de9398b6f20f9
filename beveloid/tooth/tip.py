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

from ..result import Frozen
from ..names import MEMBERS
from . import sections


#: sections scanned along the face (the pointed range is looked for between them: sections.segments)
SCAN_POINTS = 101


def _or_none(x) -> float | None:
    return float(x) if np.isfinite(x) else None


@dataclass(frozen=True)
class TipThickness(Frozen):
    """The member's transverse tip thickness along the face (mm; face coordinates z, toe at -W/2).

    A value that cannot be computed is None: in a section whose tip circle lies inside a flank's base
    circle that flank has no involute up to the tip (the tooth there is all fillet and undercut);
    ``no_involute`` lists those face ranges (status ``tip inside base circle``)."""
    member: str
    toe_mm: float | None
    middle_mm: float | None
    heel_mm: float | None
    min_mm: float | None  # the thinnest tip where it can be computed (None: nowhere)
    min_at_mm: float | None  # face coordinate of the thinnest tip
    pointed_from_mm: float | None  # face range where the tip thickness is <= 0 (None: not pointed)
    pointed_to_mm: float | None
    #: where pointed: the radius at which the flanks meet in the thinnest section, and how far below the
    #: tip cone (None: they meet at or inside the base circle, where the involutes end)
    pointed_tip_radius_mm: float | None
    pointed_tip_below_mm: float | None
    no_involute: tuple = ()  # ((from, to), ...): face ranges where the tip circle is inside a base circle

    @property
    def pointed(self) -> bool:
        return self.pointed_from_mm is not None

    def to_json(self) -> dict:
        return {"toe": self.toe_mm, "middle": self.middle_mm, "heel": self.heel_mm}

    def message(self):
        where = (f"the flanks meet at radius {self.pointed_tip_radius_mm:.4f} mm, {self.pointed_tip_below_mm:.4f} mm"
                 " below the tip cone" if self.pointed_tip_radius_mm is not None else
                 "the involutes of the flanks cross at or inside the base circle")
        return (f"pointed: {self.member} teeth from z = {self.pointed_from_mm:.3f} to {self.pointed_to_mm:.3f} mm"
                f" (face coordinate, toe at -W/2): the transverse tip thickness reaches {self.min_mm:.4f} mm at"
                f" z = {self.min_at_mm:.3f} mm, where {where}")

    def no_involute_message(self):
        spans = ", ".join(f"z = {lo:.3f} to {hi:.3f} mm" for lo, hi in self.no_involute)
        return (f"tip inside base circle: {self.member} teeth at {spans} (face coordinate, toe at -W/2): the tip"
                " circle lies inside a flank's base circle, the flank has no involute up to the tip (all fillet"
                " and undercut); the tip thickness is not computed there (null)")


def thickness(geometry, member: str, z_face):
    """Transverse arc thickness (mm) at the tip-cone radius of the section(s) z_face (NaN: no involute there)."""
    return sections.section(geometry, member, z_face).tip_arc_thickness


def pointed_tip_radius(geometry, member: str, z_face: float) -> float | None:
    """Radius (mm) where the two flanks meet in the section z_face (the tooth's angular thickness is 0),
    between the larger base circle and the tip circle; None when they do not meet there."""
    s = sections.section(geometry, member, z_face)
    lo = max(float(s.base_radius_left), float(s.base_radius_right)) * (1 + 1e-12)
    hi = float(s.tip_radius)
    f = lambda R: float(sections.thickness_at_radius(geometry, member, z_face, R).thickness_angle)  # noqa: E731
    if not hi > lo:
        return None
    f_lo, f_hi = f(lo), f(hi)
    if not (sections.classify(f_lo) == sections.POSITIVE and sections.classify(f_hi) == sections.NOT_POSITIVE):
        return None
    return float(sections.transition(f, lo, hi, f_lo, f_hi))


def _thinnest(f, grid, values):
    """(thickness, face coordinate) of the thinnest tip where it can be computed, or (None, None)."""
    finite = np.isfinite(values)
    if not finite.any():
        return None, None
    k = int(np.nanargmin(np.where(finite, values, np.nan)))
    cands = [(float(values[k]), float(grid[k]))]
    lo, hi = max(k - 1, 0), min(k + 1, len(grid) - 1)
    if finite[lo] and finite[hi] and hi > lo:
        penalised = lambda zf: (lambda v: v if np.isfinite(v) else np.inf)(f(zf))  # noqa: E731
        with np.errstate(invalid="ignore"):
            from scipy.optimize import minimize_scalar  # here, not at import: scipy.optimize costs every command ~0.3 s
            best = minimize_scalar(penalised, bounds=(grid[lo], grid[hi]), method="bounded", options={"xatol": 1e-10})
        if np.isfinite(best.fun):
            cands.append((float(best.fun), float(best.x)))
    return min(cands)


def tip_thickness(geometry, member: str, n: int = SCAN_POINTS) -> TipThickness:
    w = sections.half_face(geometry, member)
    f = lambda zf: float(thickness(geometry, member, zf))  # noqa: E731
    grid = sections.face_grid(geometry, member, n)
    values = thickness(geometry, member, grid)
    min_mm, min_at = _thinnest(f, grid, values)
    toe, mid, heel = (_or_none(v) for v in thickness(geometry, member, np.array([-w, 0.0, w])))
    segs = sections.segments(f, grid, values=values)
    none = tuple((lo, hi) for lo, hi, c in segs if c == sections.INVALID)
    pointed = [(lo, hi) for lo, hi, c in segs if c == sections.NOT_POSITIVE]
    if not pointed:
        return TipThickness(member, toe, mid, heel, min_mm, min_at, None, None, None, None, none)
    radius = pointed_tip_radius(geometry, member, min_at)
    tip = float(sections.section(geometry, member, min_at).tip_radius)
    below = tip - radius if radius is not None else None
    return TipThickness(member, toe, mid, heel, min_mm, min_at, pointed[0][0], pointed[-1][1], radius, below, none)


def tip_thicknesses(geometry) -> dict:
    return {m: tip_thickness(geometry, m) for m in MEMBERS}

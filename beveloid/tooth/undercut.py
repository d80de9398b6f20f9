"""Undercut along the face, per member and flank (definitions: derivations/tooth_sections.py).

In the transverse section at face coordinate z (``sections``), flank f is undercut when the rack's
form point (where its straight edge starts: l = l_t, the tip round's junction; l = 0 on a sharp
rack) reaches below the interference point T (where the line of action touches the base circle):
``undercut_depth`` = d - r sin^2(alpha_t) > 0, with d the form point's depth below the generating
pitch line and alpha_t the section's transverse pressure angle.  That depth (mm, along the rack's
depth direction in the section) is how far below the involute's start the cutter reaches: the
profile shift x m_t the section lacks.  Crowning is not included (a few um).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..result import Frozen
from ..names import FLANKS, MEMBERS
from . import sections

#: absolute tolerance (mm) on the face coordinates of the range's ends
XTOL_MM = 1e-10
#: sections scanned along the face per flank (the undercut is looked for between them: sections.segments)
SCAN_POINTS = 41


@dataclass(frozen=True)
class Undercut(Frozen):
    """The face range (face coordinates, mm) where one flank is undercut, and the largest depth there."""
    member: str
    flank: str
    from_mm: float
    to_mm: float
    depth_mm: float
    at_mm: float  # where the depth is largest

    def to_json(self) -> dict:
        return {"from_mm": self.from_mm, "to_mm": self.to_mm, "depth_mm": self.depth_mm}

    def message(self):
        return (f"undercut: {self.member} {self.flank} flank from z = {self.from_mm:.3f} to {self.to_mm:.3f} mm"
                f" (face coordinate, toe at -W/2): the rack's form point reaches up to {self.depth_mm:.4f} mm"
                f" below the involute's start (at z = {self.at_mm:.3f} mm)")


def depth(geometry, member: str, flank: str, z_face):
    """undercut_depth (mm, > 0: undercut) of the flank in the section(s) z_face."""
    return getattr(sections.section(geometry, member, z_face), f"undercut_depth_{flank}")


def flank_undercut(geometry, member: str, flank: str, n: int = SCAN_POINTS) -> Undercut | None:
    """The undercut range of one flank within the face, or None."""
    f = lambda zf: float(depth(geometry, member, flank, zf))  # noqa: E731
    grid = sections.face_grid(geometry, member, n)
    with np.errstate(invalid="ignore", divide="ignore"):  # NaN: a section that cannot be computed
        values = depth(geometry, member, flank, grid)  # the scan, all sections in one call
    ranges = sections.ranges_of(f, grid, sections.POSITIVE, XTOL_MM, values)
    if not ranges:
        return None
    lo, hi = ranges[0][0], ranges[-1][1]
    cands = [lo, hi] + [z for z in grid if lo <= z <= hi]
    at = max(cands, key=f)
    return Undercut(member, flank, lo, hi, f(at), float(at))


def undercut(geometry) -> dict:
    """{member: {flank: Undercut or None}}."""
    return {m: {fl: flank_undercut(geometry, m, fl) for fl in FLANKS} for m in MEMBERS}

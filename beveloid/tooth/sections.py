"""A member's transverse sections along the face (generated/tooth_sections.py, derived in
derivations/tooth_sections.py), and the face coordinate every whole-tooth check reports in.

The face coordinate ``z_face`` (mm) is measured in the member frame from the face centre (the
working pitch circle, z = b_c) toward the heel: the toe is at -W/2, the heel at +W/2.  In S_i the
section lies at z = b_c + z_face when the toe is the lower end (cone angle >= 0), else at
b_c - z_face.
"""
from __future__ import annotations

import numpy as np

from ..generated import layouts, tooth_sections

MEMBERS = ("pinion", "gear")
FLANKS = ("left", "right")
#: the three sections the JSON reports, by their face coordinate in units of W/2
ENDS = (("toe", -1.0), ("middle", 0.0), ("heel", 1.0))


def section_params(geometry, member: str) -> np.ndarray:
    """The member's ``layouts.ToothSectionParams`` vector."""
    m = geometry.member(member)
    values = dict(geometry.surface_values(member), tip_height_mm=m.tip_height_mm,
                  cutter_tip_radius_mm=m.cutter_tip_radius_mm)
    return np.asarray(layouts.ToothSectionParams.pack(values), dtype=float)


def orientation(geometry, member: str) -> float:
    """+1 when the toe is the member frame's lower face end, else -1."""
    toe, heel = geometry.member(member).face_limits
    return 1.0 if heel >= toe else -1.0


def member_z(geometry, member: str, z_face):
    """Axial position in S_i of the face coordinate(s) z_face."""
    m = geometry.member(member)
    return m.reference_section_offset_mm + orientation(geometry, member) * np.asarray(z_face, dtype=float)


def face_z(geometry, member: str, z):
    """Face coordinate of axial position(s) z of S_i (inverse of member_z)."""
    m = geometry.member(member)
    return orientation(geometry, member) * (np.asarray(z, dtype=float) - m.reference_section_offset_mm)


def half_face(geometry, member: str) -> float:
    return geometry.member(member).face_width_mm / 2


def section(geometry, member: str, z_face):
    """``tooth_sections.TransverseSection`` at face coordinate(s) z_face."""
    return tooth_sections.transverse_section(member_z(geometry, member, z_face), section_params(geometry, member))


def thickness_at_radius(geometry, member: str, z_face, radius):
    """``tooth_sections.ThicknessAtRadius`` (angular and arc thickness) at a radius of the section z_face."""
    return tooth_sections.thickness_at_radius(member_z(geometry, member, z_face), radius,
                                              section_params(geometry, member))


def face_grid(geometry, member: str, n: int = 201) -> np.ndarray:
    w = half_face(geometry, member)
    return np.linspace(-w, w, n)


def sign_change_roots(f, grid, values, xtol=1e-12):
    """Every root of the scalar function f between consecutive grid points where ``values`` changes sign."""
    from scipy.optimize import brentq

    out = []
    for k in np.nonzero(np.sign(values[:-1]) * np.sign(values[1:]) < 0)[0]:
        out.append(brentq(f, grid[k], grid[k + 1], xtol=xtol, rtol=4 * np.finfo(float).eps))
    return out


def positive_ranges(f, grid, xtol=1e-12):
    """[(from, to)] of the grid's span where the scalar function f > 0 (ends refined by bisection)."""
    values = np.array([f(x) for x in grid])
    cuts = sign_change_roots(f, grid, values, xtol)
    edges = [grid[0]] + cuts + [grid[-1]]
    ranges = []
    for lo, hi in zip(edges[:-1], edges[1:]):
        if f(0.5 * (lo + hi)) > 0:
            ranges.append((float(lo), float(hi)))
    return ranges

"""A member's transverse sections along the face (generated/tooth_sections.py, derived in
derivations/tooth_sections.py), and the face coordinate every whole-tooth check reports in.

The face coordinate ``z_face`` (mm) is measured in the member frame from the face centre (the
working pitch circle, z = b_c) toward the heel: the toe is at -W/2, the heel at +W/2.  In S_i the
section lies at z = b_c + z_face when the toe is the lower end (cone angle >= 0), else at
b_c - z_face.

Every function here takes one design's PairGeometry (floats) or the designs of an exploration (a
PairGeometry of arrays, ``explore.contact.geometry``): face coordinates then carry the designs on
their first axis, ``(n, ...)``, and each design's values broadcast over the rest.
"""
from __future__ import annotations

import numpy as np

from ..generated import layouts, tooth_sections
from ..geometry import pack_rows

#: the three sections the JSON reports, by their face coordinate in units of W/2
ENDS = (("toe", -1.0), ("middle", 0.0), ("heel", 1.0))


def section_params(geometry, member: str) -> np.ndarray:
    """The member's ``layouts.ToothSectionParams`` vector ((n, fields) for n designs)."""
    m = geometry.member(member)
    values = dict(geometry.surface_values(member), tip_height_mm=m.tip_height_mm,
                  cutter_tip_radius_mm=m.cutter_tip_radius_mm)
    if np.ndim(m.cone_angle):  # n designs
        return pack_rows(layouts.ToothSectionParams, values)
    return np.asarray(layouts.ToothSectionParams.pack(values), dtype=float)  # one: the checks' root searches call it often


def _per_design(x, like):
    """A member's value: a float as it is, the (n,) values of n designs shaped to broadcast against
    ``like`` (designs on its first axis)."""
    if np.ndim(x) == 0:
        return x
    x = np.asarray(x)
    return x.reshape(x.shape + (1,) * (np.ndim(like) - x.ndim))


def orientation(geometry, member: str):
    """+1 when the toe is the member frame's lower face end, else -1 (per design for n designs)."""
    toe, heel = geometry.member(member).face_limits
    if np.ndim(toe):
        return np.where(heel >= toe, 1.0, -1.0)
    return 1.0 if heel >= toe else -1.0


def member_z(geometry, member: str, z_face):
    """Axial position in S_i of the face coordinate(s) z_face."""
    m = geometry.member(member)
    z_face = np.asarray(z_face, dtype=float)
    return (_per_design(m.reference_section_offset_mm, z_face)
            + _per_design(orientation(geometry, member), z_face) * z_face)


def face_z(geometry, member: str, z):
    """Face coordinate of axial position(s) z of S_i (inverse of member_z)."""
    m = geometry.member(member)
    z = np.asarray(z, dtype=float)
    return _per_design(orientation(geometry, member), z) * (z - _per_design(m.reference_section_offset_mm, z))


def half_face(geometry, member: str):
    return geometry.member(member).face_width_mm / 2


def _params_for(params: np.ndarray, z) -> np.ndarray:
    """Section parameters (fields,) or (n, fields) shaped to broadcast against the axial positions z."""
    if params.ndim == 1:
        return params
    return params.reshape(params.shape[:1] + (1,) * (np.ndim(z) - 1) + params.shape[1:])


def section(geometry, member: str, z_face):
    """``tooth_sections.TransverseSection`` at face coordinate(s) z_face.

    The tip fields (``tip_thickness_angle``, ``tip_arc_thickness``) are NaN, without a warning, in a
    section whose tip circle lies inside a flank's base circle: that flank has no involute there
    (the tooth is all fillet and undercut); the tip check reports it as a status.
    """
    z = member_z(geometry, member, z_face)
    with np.errstate(invalid="ignore"):
        return tooth_sections.transverse_section(z, _params_for(section_params(geometry, member), z))


def thickness_at_radius(geometry, member: str, z_face, radius):
    """``tooth_sections.ThicknessAtRadius`` (angular and arc thickness) at a radius of the section z_face;
    NaN, without a warning, at a radius inside a flank's base circle (no involute there)."""
    z = member_z(geometry, member, z_face)
    with np.errstate(invalid="ignore"):
        return tooth_sections.thickness_at_radius(z, radius, _params_for(section_params(geometry, member), z))


def face_grid(geometry, member: str, n: int = 201) -> np.ndarray:
    """n face coordinates from toe to heel ((designs, n) for n designs)."""
    w = half_face(geometry, member)
    return np.linspace(-w, w, n, axis=-1)


# ------------------------------------------------------------------------------------------------
# The one root finder of the whole-tooth checks: scan first (NaN marks a point outside the
# function's domain), bracket between neighbouring scan points, then solve.
# ------------------------------------------------------------------------------------------------

#: the class of a value: > 0, <= 0, or not computable (NaN)
POSITIVE, NOT_POSITIVE, INVALID = "positive", "not positive", "invalid"
_BISECTIONS = 60


def classify(value: float) -> str:
    if not np.isfinite(value):
        return INVALID
    return POSITIVE if value > 0 else NOT_POSITIVE


def scan(f, grid) -> np.ndarray:
    """f at the grid points (NaN where it cannot be evaluated); numpy's warnings on invalid values
    are the NaNs themselves, not reported."""
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.array([f(x) for x in grid], dtype=float)


def _bisect_class(f, a, b, class_a, xtol):
    """Bisection on the class of f between a (class_a) and b (another class): the point where it changes."""
    for _ in range(_BISECTIONS):
        if abs(b - a) <= xtol:
            break
        mid = 0.5 * (a + b)
        with np.errstate(invalid="ignore", divide="ignore"):
            if classify(float(f(mid))) == class_a:
                a = mid
            else:
                b = mid
    return 0.5 * (a + b)


class _Invalid(ArithmeticError):
    pass


def transition(f, a, b, fa, fb, xtol=1e-12) -> float:
    """Where f changes class between a and b (classes of fa and fb differ): brentq where both ends are
    finite and f stays finite between them, else bisection on the class (the edge of f's domain)."""
    from scipy.optimize import brentq

    ca = classify(fa)
    if ca == INVALID or classify(fb) == INVALID or fa == 0.0:
        return a if fa == 0.0 else _bisect_class(f, a, b, ca, xtol)
    if fb == 0.0:
        return b

    def finite(x):
        with np.errstate(invalid="ignore", divide="ignore"):
            v = float(f(x))
        if not np.isfinite(v):
            raise _Invalid
        return v

    try:
        return brentq(finite, a, b, xtol=xtol, rtol=4 * np.finfo(float).eps)
    except _Invalid:  # f is not computable somewhere inside: the class bisection still finds a change
        return _bisect_class(f, a, b, ca, xtol)


def segments(f, grid, xtol=1e-12, values=None):
    """[(from, to, class)] covering the grid's span: where f > 0, <= 0 or cannot be computed (NaN),
    the ends between grid points refined by :func:`transition`."""
    values = scan(f, grid) if values is None else np.asarray(values, dtype=float)
    classes = [classify(v) for v in values]
    out, lo = [], float(grid[0])
    for k in range(len(grid) - 1):
        if classes[k] != classes[k + 1]:
            cut = float(transition(f, grid[k], grid[k + 1], values[k], values[k + 1], xtol))
            out.append((lo, cut, classes[k]))
            lo = cut
    out.append((lo, float(grid[-1]), classes[-1]))
    return [seg for seg in out if seg[1] > seg[0] or len(out) == 1]


def ranges_of(f, grid, cls, xtol=1e-12, values=None):
    """[(from, to)] of the grid's span where f is of class ``cls`` (:func:`segments`)."""
    return [(lo, hi) for lo, hi, c in segments(f, grid, xtol, values) if c == cls]


def positive_ranges(f, grid, xtol=1e-12):
    """[(from, to)] of the grid's span where the scalar function f > 0 (ends refined)."""
    return ranges_of(f, grid, POSITIVE, xtol)

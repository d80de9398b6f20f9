"""The checks of a design besides the paper's equations (see the package docstring), for arrays of
designs, with named outcomes; and the one-line refusals that explain an outcome for one design.

:func:`check` runs every check in the order below on the design equations' outputs of n designs and
returns the first failing :class:`Outcome` of each (``Outcome.OK`` when all pass).  The geometry the
checks read (tip radius and thickness, form circle, undercut depth) comes from functions that take
a member record by field name -- a :class:`beveloid.design.MemberDesign` (one design) or a
:class:`MemberArrays` (many designs, the same field names) -- so a check and its message read the same
numbers.  Refusal messages name the keys, the values and which way to move.
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..names import Flank, Member
from ..spec import DesignSpec
from ..status import Outcome
from .kernels import deg_text, member_outputs, num_text
from .members import DesignError, MemberDesign

#: Teeth whose transverse tip thickness is <= this times m_n are "pointed" (an error).
POINTED_TIP_FACTOR = 0.2
#: |beta2| at or above this (rad) is rejected.
MAX_GEAR_HELIX_ANGLE = math.radians(80.0)
#: the labels by code (index = Outcome value)
LABELS = tuple(o.label for o in Outcome)


class MemberArrays(NamedTuple):
    """One member of n designs by MemberDesign's field names (arrays; radians and mm)."""

    name: str
    teeth: np.ndarray
    normal_module_mm: np.ndarray
    helix_angle: np.ndarray
    cone_angle: np.ndarray
    profile_shift: np.ndarray
    reference_pitch_radius_mm: np.ndarray
    working_pitch_radius_mm: np.ndarray
    working_mounting_distance_mm: np.ndarray
    transverse_pressure_angle_left: np.ndarray
    transverse_pressure_angle_right: np.ndarray
    face_width_mm: np.ndarray
    addendum_coefficient: np.ndarray
    cutter_addendum_coefficient: np.ndarray
    reference_section_offset_mm: np.ndarray
    sin_pitch_point_angle: np.ndarray
    cos_pitch_point_angle: np.ndarray

    @property
    def pitch_point_angle(self) -> np.ndarray:
        """theta_i of P (rad), as MemberDesign's: atan2 of the generated sine and cosine."""
        return np.array([math.atan2(s, c) for s, c in zip(self.sin_pitch_point_angle, self.cos_pitch_point_angle)])

    @property
    def rack_shift_mm(self) -> np.ndarray:
        return _rack_shift_mm(self)

    @property
    def cutter_addendum_mm(self) -> np.ndarray:
        return self.cutter_addendum_coefficient * self.normal_module_mm

    def take(self, idx) -> "MemberArrays":
        """The designs idx."""
        return MemberArrays(self.name, *(np.asarray(v)[idx] for v in self[1:]))


def member_arrays(values: dict, q: dict, name: str) -> MemberArrays:
    """Member ``name`` of n designs from the spec values (dotted key -> (n,)) and the kernels' outputs q."""
    o = member_outputs(q, name)
    return MemberArrays(
        name, values[f"{name}.teeth"], values["pair.normal_module_mm"], o.helix_angle, o.cone_angle,
        values["pinion.profile_shift"] if name == Member.PINION else q["x_t2"], o.reference_pitch_radius_mm,
        o.working_pitch_radius_mm, o.working_mounting_distance_mm, o.transverse_pressure_angle_left,
        o.transverse_pressure_angle_right, values[f"{name}.face_width_mm"], values[f"{name}.addendum_coefficient"],
        values[f"{name}.cutter_addendum_coefficient"], values[f"{name}.reference_section_offset_mm"],
        o.sin_pitch_point_angle, o.cos_pitch_point_angle)


def _flank_angles(m):
    return ((Flank.LEFT, m.transverse_pressure_angle_left), (Flank.RIGHT, m.transverse_pressure_angle_right))


def _rack_shift_mm(m):
    return m.profile_shift * m.normal_module_mm * np.cos(m.cone_angle) / np.cos(m.helix_angle)


def tooth_tip(m):
    """In the reference transverse section: (tip radius r_a, {flank: base radius r_b}, transverse tip
    thickness s_a; nan where the tip circle lies inside a base circle) in mm."""
    m_n = m.normal_module_mm
    m_t = m_n / np.cos(m.helix_angle)
    r = m.reference_pitch_radius_mm
    aPL, aPR = m.transverse_pressure_angle_left, m.transverse_pressure_angle_right
    s_t = math.pi * m_t / 2 + m.profile_shift * m_t * (np.tan(aPL) + np.tan(aPR))
    r_a = r + m.profile_shift * m_t + m.addendum_coefficient * m_n / np.cos(m.cone_angle)
    angle = s_t / r
    r_b = {}
    with np.errstate(all="ignore"):
        for flank, aP in _flank_angles(m):
            r_b[flank] = r * np.cos(aP)
            ac = np.arccos(r_b[flank] / r_a)
            angle = angle + ((np.tan(aP) - aP) - (np.tan(ac) - ac))
    return r_a, r_b, r_a * angle


def undercut_depths(m):
    """{flank: (cutter tip depth below the pitch circle, interference point depth r sin^2 alpha_P)} in
    the reference section (mm); the flank is undercut where the first exceeds the second."""
    depth = (m.cutter_addendum_coefficient * m.normal_module_mm - _rack_shift_mm(m)) / np.cos(m.cone_angle)
    return {flank: (depth, m.reference_pitch_radius_mm * np.sin(aP) ** 2) for flank, aP in _flank_angles(m)}


def pitch_point_margins(m) -> dict:
    """Where the pitch point P lies on each flank of ``m``, in its working-pitch-circle section.

    P is at the working pitch radius r_w in the transverse section z = b_c (the frame origin is in the
    reference section).  That section is a shifted spur section: base radius r cos(alpha_P), tip radius
    ``r + (h_a m_n + s)/cos(gamma) + b_c tan(gamma)``, and the rack tip (where its straight edge starts)
    at the depth ``h = (a - s)/cos(gamma) - b_c tan(gamma)`` below the pitch circle.  The profile point at
    radius rho is cut by the rack point at depth ``t = sin(alpha_P) (r sin(alpha_P) - sqrt(rho^2 - r_b^2))``;
    it is on the active profile when ``t <= h`` (above the form circle) and rho <= tip radius.

    Returns per flank (radius of the form circle, tip radius, r_w) in mm; the form radius is the
    base radius where the rack tip reaches below the interference point (undercut).
    """
    r, r_w, zc = m.reference_pitch_radius_mm, m.working_pitch_radius_mm, m.reference_section_offset_mm
    m_n = m.normal_module_mm
    rack = _rack_shift_mm(m)
    tan_g, cos_g = np.tan(m.cone_angle), np.cos(m.cone_angle)
    tip = r + (m.addendum_coefficient * m_n + rack) / cos_g + zc * tan_g
    depth = (m.cutter_addendum_coefficient * m_n - rack) / cos_g - zc * tan_g
    out = {}
    for flank, aP in _flank_angles(m):
        r_b = r * np.cos(aP)
        along = r * np.sin(aP) - depth / np.sin(aP)  # rack tip's point on the line of action, from T
        out[flank] = (np.where(along > 0, np.hypot(r_b, along), r_b)[()], tip, r_w)
    return out


def _transverse_tangents(alpha_n, q, alpha_nw, name):
    """{flank: (reference, working) tan alpha_P numerators of member ``name``: tan(alpha_n) cos(gamma) +-
    sin(beta) sin(gamma) and the same with the working data} (> 0 for a flank leaning the right way)."""
    o = member_outputs(q, name)
    return {f: (np.tan(alpha_n) * np.cos(o.cone_angle) + f.sigma * np.sin(o.helix_angle) * np.sin(o.cone_angle),
                np.tan(alpha_nw) * np.cos(o.working_cone_angle)
                + f.sigma * np.sin(o.working_helix_angle) * np.sin(o.working_cone_angle)) for f in Flank}


def _fail(outcome, mask, code):
    outcome[(outcome == Outcome.OK) & mask] = code


def check(values: dict, q: dict, alpha_nw, outcome: np.ndarray) -> None:
    """The checks of n designs' outputs ``q`` (at their alpha_nw) in order; ``outcome`` (codes, updated in
    place) keeps the first failure of each design."""
    with np.errstate(all="ignore"):
        beta2 = q["beta2"]
        _fail(outcome, ~np.isfinite(beta2) | (np.abs(beta2) >= MAX_GEAR_HELIX_ANGLE),
              Outcome.GEAR_HELIX_ANGLE_OUT_OF_RANGE)
        alpha_n = np.radians(values["pair.normal_pressure_angle_deg"])
        bad = np.zeros(outcome.size, dtype=bool)
        for name in Member:
            for ref, work in _transverse_tangents(alpha_n, q, alpha_nw, name).values():
                bad |= ~((ref > 0) & (work > 0))
        _fail(outcome, bad, Outcome.TRANSVERSE_PRESSURE_ANGLE_NOT_POSITIVE)
        _fail(outcome, ~np.all([np.isfinite(x) for x in q.values()], axis=0), Outcome.NON_FINITE_DESIGN)
        _fail(outcome, ~((q["r_w1"] > 0) & (q["r1"] > 0) & (q["r_w2"] > 0) & (q["r2"] > 0)),
              Outcome.NON_PHYSICAL_PITCH_RADIUS)
        members = [member_arrays(values, q, name) for name in Member]
        for m in members:  # a failure of the pinion's tooth checks comes before any of the gear's
            r_a, r_b, s_a = tooth_tip(m)
            _fail(outcome, (r_a <= r_b[Flank.LEFT]) | (r_a <= r_b[Flank.RIGHT]), Outcome.TIP_INSIDE_BASE_CIRCLE)
            _fail(outcome, s_a <= POINTED_TIP_FACTOR * m.normal_module_mm, Outcome.POINTED_TEETH)
        off = np.zeros(outcome.size, dtype=bool)
        for m in members:
            for form, tip, r_w in pitch_point_margins(m).values():
                off |= ~((form <= r_w) & (r_w <= tip))
        _fail(outcome, off, Outcome.PITCH_POINT_OFF_ACTIVE_PROFILE)


# ---------------------------------------------------------------------------
# One design: the refusal that explains a failed check (one line), and the undercut notes
# ---------------------------------------------------------------------------


def _tooth_words(spec: DesignSpec, m: MemberDesign):
    if m.name == Member.PINION:
        raise_hint = "increase pinion.profile_shift or pinion.teeth"
        lower_hint = "reduce pinion.profile_shift or pinion.addendum_coefficient"
        keys = ("pinion.profile_shift", "pinion.teeth", "pinion.addendum_coefficient")
        head = f"pinion.profile_shift = {spec.pinion.profile_shift!r}, pinion.teeth = {m.teeth}: "
    else:  # the gear's profile shift is a result: Eq 27 fixes the sum of the shifts for the offset
        raise_hint = ("reduce pinion.profile_shift or increase pair.offset_mm (Eq 27 then raises the gear's"
                      " profile shift), or increase gear.teeth")
        lower_hint = ("increase pinion.profile_shift or reduce pair.offset_mm (Eq 27 then lowers the gear's"
                      " profile shift), or reduce gear.addendum_coefficient")
        keys = ("pinion.profile_shift", "pair.offset_mm", "gear.teeth", "gear.addendum_coefficient")
        head = (f"pair.offset_mm = {spec.pair.offset_mm!r}, pinion.profile_shift ="
                f" {spec.pinion.profile_shift!r}: the gear profile shift from Eq 27 is {num_text(m.profile_shift)}"
                f" and ")
    return raise_hint, lower_hint, keys, head


def tooth_checks(spec: DesignSpec, m: MemberDesign, notes: list[str]) -> None:
    """Pointed or too thin tip (a DesignError) and undercut (a note) in the reference transverse section."""
    raise_hint, lower_hint, keys, head = _tooth_words(spec, m)
    r_a, r_b, s_a = (float(x) if not isinstance(x, dict) else {k: float(v) for k, v in x.items()}
                     for x in tooth_tip(m))
    where = f"at the reference section (tip radius {num_text(r_a)} mm)"
    for flank, rb in r_b.items():
        if r_a <= rb:
            raise DesignError(
                f"{head}{m.name} teeth: the tip circle lies inside the {flank}-flank base circle {num_text(rb)} mm"
                f" {where}; {raise_hint}", keys=keys, source=spec.source, outcome=Outcome.TIP_INSIDE_BASE_CIRCLE)
    if s_a <= POINTED_TIP_FACTOR * m.normal_module_mm:
        hint = lower_hint if m.profile_shift > 0 else raise_hint
        raise DesignError(
            f"{head}{m.name} teeth are pointed: transverse tip thickness {num_text(s_a)} mm <= {POINTED_TIP_FACTOR}"
            f" m_n = {num_text(POINTED_TIP_FACTOR * m.normal_module_mm)} mm {where}; {hint}", keys=keys,
            source=spec.source, outcome=Outcome.POINTED_TEETH)
    for flank, (depth, limit) in undercut_depths(m).items():
        if depth > limit:
            notes.append(
                f"undercut: {m.name} {flank} flank at the reference section (cutter tip {num_text(depth)} mm below the"
                f" pitch circle, interference point {num_text(limit)} mm below it; x_t = {num_text(m.profile_shift)});"
                f" {raise_hint}")


def check_pitch_point(spec: DesignSpec, m: MemberDesign, alpha_nw: float) -> None:
    """The designed contact at the pitch point P must lie on the active profile of both flanks.

    Otherwise the aligned pair has no contact near P (TCA finds the flanks apart or off the
    blank): typically alpha_nw is so small that the working pitch circle falls below the form
    circle, or so large that it passes the tip.
    """
    for flank, (form, tip, r_w) in pitch_point_margins(m).items():
        if form <= r_w <= tip:
            continue
        below = r_w < form
        where = (f"below the start of the active profile (form circle {num_text(form)} mm)" if below
                 else f"above the tip (tip circle {num_text(tip)} mm)")
        if below:
            move = (f"increase pair.offset_mm (a larger alpha_nw moves P outward) or increase"
                    f" {m.name}.cutter_addendum_coefficient (a deeper cut lowers the form circle)")
            keys = ("pair.offset_mm", f"{m.name}.cutter_addendum_coefficient")
        else:
            move = (f"reduce pair.offset_mm (a smaller alpha_nw moves P inward) or increase"
                    f" {m.name}.addendum_coefficient")
            keys = ("pair.offset_mm", f"{m.name}.addendum_coefficient")
        raise DesignError(
            f"pair.offset_mm = {spec.pair.offset_mm!r}: the design's pitch point P (working pitch radius"
            f" {num_text(r_w)} mm, alpha_nw = {deg_text(alpha_nw)} deg) lies {where} of the {m.name} teeth, {flank}"
            f" flank, so the pair cannot mesh at P; {move}", keys=keys, source=spec.source,
            outcome=Outcome.PITCH_POINT_OFF_ACTIVE_PROFILE)


def check_transverse_pressure_angles(spec: DesignSpec, q: dict[str, float], alpha_nw: float) -> None:
    """Every transverse pressure angle, reference and working, must be positive.

    Tilted rack: tan(alpha_P) = (tan(alpha_n) cos(gamma) +- sin(beta) sin(gamma)) / cos(beta), and the same
    with the working data.  With alpha_P <= 0 a flank leans past the radial direction; the generated
    kernels take alpha_Pw = arccos(xi_t cos(alpha_P)) >= 0, so Eqs 22 and 27 would silently lose the sign.
    """
    alpha_n = math.radians(spec.pair.normal_pressure_angle_deg)
    for name in Member:
        o = member_outputs(q, name)
        for flank, (ref, work) in _transverse_tangents(alpha_n, q, alpha_nw, name).items():
            if ref > 0 and work > 0:
                continue
            which = "reference" if not ref > 0 else f"working (alpha_nw = {deg_text(alpha_nw)} deg)"
            angle = math.atan2(ref if not ref > 0 else work, math.cos(o.helix_angle if not ref > 0
                                                                     else o.working_helix_angle))
            if name == Member.PINION:
                head = (f"pinion.helix_angle_deg = {spec.pinion.helix_angle_deg!r}, pinion.cone_angle_deg ="
                        f" {spec.pinion.cone_angle_deg!r}")
                move = "reduce |pinion.helix_angle_deg| or |pinion.cone_angle_deg|"
                keys = ("pinion.helix_angle_deg", "pinion.cone_angle_deg", "pair.normal_pressure_angle_deg")
            else:
                head = f"gear.cone_angle_deg = {spec.gear.cone_angle_deg!r} (gear helix angle {deg_text(o.helix_angle)} deg)"
                move = "reduce |gear.cone_angle_deg| or the gear helix angle (via pinion.helix_angle_deg)"
                keys = ("gear.cone_angle_deg", "pinion.helix_angle_deg", "pair.normal_pressure_angle_deg")
            raise DesignError(
                f"{head}: the {name}'s {flank}-flank {which} transverse pressure angle is {deg_text(angle)} deg <= 0"
                f" (tan alpha_P = (tan alpha_n cos gamma +- sin beta sin gamma) / cos beta); {move},"
                f" or increase pair.normal_pressure_angle_deg", keys=keys, source=spec.source,
                outcome=Outcome.TRANSVERSE_PRESSURE_ANGLE_NOT_POSITIVE)

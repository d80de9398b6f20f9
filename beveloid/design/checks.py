"""Checks of a design besides the paper's equations (see the package docstring): tooth tips, undercut,
transverse pressure angles and the pitch point on the active profile."""
from __future__ import annotations

import math

from ..spec import DesignSpec
from .kernels import deg_text, member_outputs, num_text
from .members import DesignError, MemberDesign

#: Teeth whose transverse tip thickness is <= this times m_n are "pointed" (an error).
POINTED_TIP_FACTOR = 0.2


def _inv(t: float) -> float:
    """inv(alpha) from alpha."""
    return math.tan(t) - t


def tooth_checks(spec: DesignSpec, m: MemberDesign, notes: list[str]) -> None:
    """Pointed or too thin tip (error) and undercut (note) in the reference transverse section."""
    m_n = m.normal_module_mm
    m_t = m.transverse_module_mm
    r = m.reference_pitch_radius_mm
    aPL, aPR = m.transverse_pressure_angle_left, m.transverse_pressure_angle_right
    s_t = math.pi * m_t / 2 + m.profile_shift * m_t * (math.tan(aPL) + math.tan(aPR))
    r_a = r + m.profile_shift * m_t + m.addendum_coefficient * m_n / math.cos(m.cone_angle)
    if m.name == "pinion":
        raise_hint = "increase pinion.profile_shift or pinion.teeth"
        lower_hint = "reduce pinion.profile_shift or pinion.addendum_coefficient"
        keys = ("pinion.profile_shift", "pinion.teeth", "pinion.addendum_coefficient")
    else:  # the gear's profile shift is a result: Eq 27 fixes the sum of the shifts for the offset
        raise_hint = ("reduce pinion.profile_shift or increase pair.offset_mm (Eq 27 then raises the gear's"
                      " profile shift), or increase gear.teeth")
        lower_hint = ("increase pinion.profile_shift or reduce pair.offset_mm (Eq 27 then lowers the gear's"
                      " profile shift), or reduce gear.addendum_coefficient")
        keys = ("pinion.profile_shift", "pair.offset_mm", "gear.teeth", "gear.addendum_coefficient")
    if m.name == "pinion":
        head = f"pinion.profile_shift = {spec.pinion.profile_shift!r}, pinion.teeth = {m.teeth}: "
    else:
        head = (f"pair.offset_mm = {spec.pair.offset_mm!r}, pinion.profile_shift ="
                f" {spec.pinion.profile_shift!r}: the gear profile shift from Eq 27 is {num_text(m.profile_shift)}"
                f" and ")
    where = f"at the reference section (tip radius {num_text(r_a)} mm)"
    angle = s_t / r
    for flank, aP in (("left", aPL), ("right", aPR)):
        r_b = r * math.cos(aP)
        if r_a <= r_b:
            raise DesignError(
                f"{head}{m.name} teeth: the tip circle lies inside the {flank}-flank base circle {num_text(r_b)} mm {where};"
                f" {raise_hint}", keys=keys, source=spec.source)
        angle += _inv(aP) - _inv(math.acos(r_b / r_a))
    s_a = r_a * angle
    if s_a <= POINTED_TIP_FACTOR * m_n:
        hint = lower_hint if m.profile_shift > 0 else raise_hint
        raise DesignError(
            f"{head}{m.name} teeth are pointed: transverse tip thickness {num_text(s_a)} mm <= {POINTED_TIP_FACTOR} m_n ="
            f" {num_text(POINTED_TIP_FACTOR * m_n)} mm {where}; {hint}", keys=keys, source=spec.source)
    depth = (m.cutter_addendum_mm - m.rack_shift_mm) / math.cos(m.cone_angle)
    for flank, aP in (("left", aPL), ("right", aPR)):
        limit = r * math.sin(aP) ** 2
        if depth > limit:
            notes.append(
                f"undercut: {m.name} {flank} flank at the reference section (cutter tip {num_text(depth)} mm below the"
                f" pitch circle, interference point {num_text(limit)} mm below it; x_t = {num_text(m.profile_shift)});"
                f" {raise_hint}")


def pitch_point_margins(m: MemberDesign) -> dict[str, tuple[float, float, float]]:
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
    tan_g, cos_g = math.tan(m.cone_angle), math.cos(m.cone_angle)
    tip = r + (m.addendum_coefficient * m.normal_module_mm + m.rack_shift_mm) / cos_g + zc * tan_g
    depth = (m.cutter_addendum_mm - m.rack_shift_mm) / cos_g - zc * tan_g
    out = {}
    for flank, aP in (("left", m.transverse_pressure_angle_left), ("right", m.transverse_pressure_angle_right)):
        r_b = r * math.cos(aP)
        along = r * math.sin(aP) - depth / math.sin(aP)  # rack tip's point on the line of action, from T
        form = math.hypot(r_b, along) if along > 0 else r_b
        out[flank] = (form, tip, r_w)
    return out


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
            f" flank, so the pair cannot mesh at P; {move}", keys=keys, source=spec.source)


def check_transverse_pressure_angles(spec: DesignSpec, q: dict[str, float], alpha_nw: float) -> None:
    """Every transverse pressure angle, reference and working, must be positive.

    Tilted rack: tan(alpha_P) = (tan(alpha_n) cos(gamma) +- sin(beta) sin(gamma)) / cos(beta), and the same
    with the working data.  With alpha_P <= 0 a flank leans past the radial direction; the generated
    kernels take alpha_Pw = arccos(xi_t cos(alpha_P)) >= 0, so Eqs 22 and 27 would silently lose the sign.
    """
    src = spec.source
    alpha_n = math.radians(spec.pair.normal_pressure_angle_deg)
    for name in ("pinion", "gear"):
        o = member_outputs(q, name)
        b, g = o.helix_angle, o.cone_angle
        bw, gw = o.working_helix_angle, o.working_cone_angle
        for sigma, word in ((1, "left"), (-1, "right")):
            ref = math.tan(alpha_n) * math.cos(g) + sigma * math.sin(b) * math.sin(g)
            work = math.tan(alpha_nw) * math.cos(gw) + sigma * math.sin(bw) * math.sin(gw)
            if ref > 0 and work > 0:
                continue
            which = "reference" if not ref > 0 else f"working (alpha_nw = {deg_text(alpha_nw)} deg)"
            angle = math.atan2(ref if not ref > 0 else work, math.cos(b if not ref > 0 else bw))
            if name == "pinion":
                head = (f"pinion.helix_angle_deg = {spec.pinion.helix_angle_deg!r}, pinion.cone_angle_deg ="
                        f" {spec.pinion.cone_angle_deg!r}")
                move = "reduce |pinion.helix_angle_deg| or |pinion.cone_angle_deg|"
                keys = ("pinion.helix_angle_deg", "pinion.cone_angle_deg", "pair.normal_pressure_angle_deg")
            else:
                head = f"gear.cone_angle_deg = {spec.gear.cone_angle_deg!r} (gear helix angle {deg_text(b)} deg)"
                move = "reduce |gear.cone_angle_deg| or the gear helix angle (via pinion.helix_angle_deg)"
                keys = ("gear.cone_angle_deg", "pinion.helix_angle_deg", "pair.normal_pressure_angle_deg")
            raise DesignError(
                f"{head}: the {name}'s {word}-flank {which} transverse pressure angle is {deg_text(angle)} deg <= 0"
                f" (tan alpha_P = (tan alpha_n cos gamma +- sin beta sin gamma) / cos beta); {move},"
                f" or increase pair.normal_pressure_angle_deg", keys=keys, source=src)

"""The direct design (first chart of Fig. 7): alpha_nw from Eq 17, then Eqs 12-27, then the checks."""
from __future__ import annotations

import math

from ..spec import DesignSpec
from . import checks
from .kernels import deg_text, direct_outputs, member_outputs, num_text
from .members import DesignError, DesignResult, MemberDesign
from .solve import check_cone_angles, solve_alpha_nw, spec_constants

#: |beta2| at or above this (rad) is rejected.
MAX_GEAR_HELIX_ANGLE = math.radians(80.0)


def design(spec: DesignSpec) -> DesignResult:
    """Direct design (Fig. 7, first chart): solve alpha_nw from Eq 17, then evaluate Eqs 12-27.

    Raises :class:`DesignError` when the request has no physical solution.
    """
    if not isinstance(spec, DesignSpec):
        raise TypeError(f"design() needs a DesignSpec, not {type(spec).__name__} (see beveloid.spec.load_spec)")
    c = spec_constants(spec)
    check_cone_angles(spec, c["gamma1"], c["gamma2"])
    alpha_nw, resid, notes = solve_alpha_nw(spec, c)
    q = {k: float(v) for k, v in direct_outputs(alpha_nw, c).items()}
    return finish(spec, q, alpha_nw, offset=c["E"], residual=resid, notes=notes, procedure="direct")


def member_design(spec: DesignSpec, q: dict[str, float], name: str, m_n: float) -> MemberDesign:
    """The design of member ``name`` from the kernels' outputs ``q`` and the spec's blank data."""
    ms = getattr(spec, name)
    o = member_outputs(q, name)
    return MemberDesign(
        name=name,
        teeth=int(ms.teeth),
        normal_module_mm=m_n,
        helix_angle=o.helix_angle,
        cone_angle=o.cone_angle,
        profile_shift=(float(ms.profile_shift) if name == "pinion" else q["x_t2"]),
        transverse_angular_factor=o.transverse_angular_factor,
        mounting_distance_mm=o.mounting_distance_mm,
        working_mounting_distance_mm=o.working_mounting_distance_mm,
        working_cone_angle=o.working_cone_angle,
        working_helix_angle=o.working_helix_angle,
        working_pitch_radius_mm=o.working_pitch_radius_mm,
        reference_pitch_radius_mm=o.reference_pitch_radius_mm,
        transverse_pressure_angle_left=o.transverse_pressure_angle_left,
        transverse_pressure_angle_right=o.transverse_pressure_angle_right,
        working_transverse_pressure_angle_left=o.working_transverse_pressure_angle_left,
        working_transverse_pressure_angle_right=o.working_transverse_pressure_angle_right,
        fpd_angle_left=o.fpd_angle_left,
        fpd_angle_right=o.fpd_angle_right,
        pitch_point_angle=math.atan2(o.sin_pitch_point_angle, o.cos_pitch_point_angle),
        face_width_mm=float(ms.face_width_mm),
        addendum_coefficient=float(ms.addendum_coefficient),
        cutter_addendum_coefficient=float(ms.cutter_addendum_coefficient),
        reference_section_offset_mm=float(ms.reference_section_offset_mm),
    )


def finish(spec: DesignSpec, q: dict[str, float], alpha_nw: float, *, offset: float, residual: float,
           notes: list[str], procedure: str) -> DesignResult:
    """The checks of a design's outputs ``q`` (both procedures), then the :class:`DesignResult`."""
    src = spec.source
    beta2 = q["beta2"]
    if not math.isfinite(beta2) or abs(beta2) >= MAX_GEAR_HELIX_ANGLE:
        shown = f"{deg_text(beta2)} deg" if math.isfinite(beta2) else "not real (|sin beta2| > 1)"
        # beta2 ~ eta - beta_w1 with eta ~ delta: move beta1 toward delta
        bw2 = q["beta_w2"]
        direction = "increase" if (bw2 > 0 if math.isfinite(bw2) else True) else "reduce"
        raise DesignError(
            f"pinion.helix_angle_deg = {spec.pinion.helix_angle_deg!r}: the gear helix angle beta2 (Eq 26,"
            f" beta_w2 = eta - beta_w1 of Eq 16) is {shown}, |beta2| must stay below 80 deg;"
            f" {direction} pinion.helix_angle_deg (beta2 ~ shaft angle - beta1)",
            keys=("pinion.helix_angle_deg", "pair.shaft_angle_deg"), source=src)
    checks.check_transverse_pressure_angles(spec, q, alpha_nw)
    bad = sorted(k for k, v in q.items() if not math.isfinite(v))
    if bad:
        raise DesignError(
            f"pinion.cone_angle_deg = {spec.pinion.cone_angle_deg!r}, gear.cone_angle_deg ="
            f" {spec.gear.cone_angle_deg!r}: the design equations give non-finite {', '.join(bad)}"
            f" at alpha_nw = {deg_text(alpha_nw)} deg; increase |cone angles| or the shaft angle",
            keys=("pinion.cone_angle_deg", "gear.cone_angle_deg"), source=src)
    for name in ("pinion", "gear"):
        o = member_outputs(q, name)
        if not o.working_pitch_radius_mm > 0 or not o.reference_pitch_radius_mm > 0:
            raise DesignError(
                f"{name}.teeth = {getattr(spec, name).teeth}: non-physical {name} pitch radius"
                f" (r = {num_text(o.reference_pitch_radius_mm)}, r_w = {num_text(o.working_pitch_radius_mm)} mm);"
                f" increase {name}.teeth",
                keys=(f"{name}.teeth",), source=src)
    m_n = float(spec.pair.normal_module_mm)
    pinion = member_design(spec, q, "pinion", m_n)
    gear = member_design(spec, q, "gear", m_n)
    notes = list(notes)
    for m in (pinion, gear):
        checks.tooth_checks(spec, m, notes)
    for m in (pinion, gear):
        checks.check_pitch_point(spec, m, alpha_nw)
    return DesignResult(
        spec=spec,
        working_normal_pressure_angle=float(alpha_nw),
        normal_angular_factor=q["xi_n"],
        fpd_angle_left=q["xi_L"],
        fpd_angle_right=q["xi_R"],
        offset_mm=float(offset),
        shaft_angle=math.radians(spec.pair.shaft_angle_deg),
        normal_module_mm=m_n,
        normal_pressure_angle=math.radians(spec.pair.normal_pressure_angle_deg),
        pinion=pinion,
        gear=gear,
        notes=tuple(notes),
        offset_residual_mm=float(residual),
        procedure=procedure,
    )

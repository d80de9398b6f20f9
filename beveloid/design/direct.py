"""The direct design (first chart of Fig. 7): alpha_nw from Eq 17, then Eqs 12-27, then the checks."""
from __future__ import annotations

import math

import numpy as np

from ..spec import DesignSpec
from . import checks, refusals
from .arrays import design_arrays, spec_values
from .checks import MAX_GEAR_HELIX_ANGLE, Outcome
from .kernels import direct_outputs, member_outputs
from .members import DesignResult, MemberDesign

__all__ = ["design", "finish", "member_design", "MAX_GEAR_HELIX_ANGLE"]


def design(spec: DesignSpec) -> DesignResult:
    """Direct design (Fig. 7, first chart): solve alpha_nw from Eq 17, then evaluate Eqs 12-27.

    The design of many designs at n = 1 (:func:`beveloid.design.arrays.design_arrays`).  Raises
    :class:`DesignError` (one line explaining the failed check) when the request has no physical solution.
    """
    if not isinstance(spec, DesignSpec):
        raise TypeError(f"design() needs a DesignSpec, not {type(spec).__name__} (see beveloid.spec.load_spec)")
    a = design_arrays(spec_values(spec), scalar=True)
    outcome = Outcome(int(a.outcome[0]))
    if outcome is Outcome.ZERO_CONE_ANGLE:
        raise refusals.zero_cone_angle(spec)
    if outcome is Outcome.NO_WORKING_PRESSURE_ANGLE:
        raise refusals.no_working_pressure_angle(spec, a.constants)
    # the result's numbers from the kernel at Python scalars (also alpha_nw): numpy's 0-d and 1-element
    # evaluations may differ in the last bit (d_w2 of case 1 and case 2)
    alpha_nw = float(a.alpha_nw[0])
    q = {k: float(v) for k, v in direct_outputs(alpha_nw, a.constants).items()}
    return finish(spec, q, alpha_nw, residual=float(a.offset_residual_mm[0]),
                  notes=refusals.root_notes(a.constants, a.roots),
                  procedure="direct", outcome=outcome)


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


def finish(spec: DesignSpec, q: dict[str, float], alpha_nw: float, *, residual: float, notes: list[str],
           procedure: str, outcome: Outcome | None = None) -> DesignResult:
    """The :class:`DesignResult` of a design's outputs ``q`` (both procedures), or the refusal that explains
    its ``outcome`` (of :func:`beveloid.design.checks.check`; checked here when not given)."""
    if outcome is None:
        codes = np.zeros(1, dtype=np.int64)
        checks.check(spec_values(spec), {k: np.array([v]) for k, v in q.items()}, np.array([alpha_nw]), codes)
        outcome = Outcome(int(codes[0]))
    if outcome is Outcome.GEAR_HELIX_ANGLE_OUT_OF_RANGE:
        raise refusals.gear_helix_angle(spec, q)
    if outcome is Outcome.TRANSVERSE_PRESSURE_ANGLE_NOT_POSITIVE:
        checks.check_transverse_pressure_angles(spec, q, alpha_nw)
    if outcome is Outcome.NON_FINITE_DESIGN:
        raise refusals.non_finite(spec, q, alpha_nw)
    if outcome is Outcome.NON_PHYSICAL_PITCH_RADIUS:
        raise refusals.pitch_radius(spec, q)
    m_n = float(spec.pair.normal_module_mm)
    pinion = member_design(spec, q, "pinion", m_n)
    gear = member_design(spec, q, "gear", m_n)
    notes = list(notes)
    for m in (pinion, gear):
        checks.tooth_checks(spec, m, notes)  # the refusal of a tip inside the base circle or pointed teeth
    if outcome is Outcome.PITCH_POINT_OFF_ACTIVE_PROFILE:
        for m in (pinion, gear):
            checks.check_pitch_point(spec, m, alpha_nw)
    return DesignResult(
        spec=spec,
        working_normal_pressure_angle=float(alpha_nw),
        normal_angular_factor=q["xi_n"],
        fpd_angle_left=q["xi_L"],
        fpd_angle_right=q["xi_R"],
        offset_mm=float(spec.pair.offset_mm),
        shaft_angle=math.radians(spec.pair.shaft_angle_deg),
        normal_module_mm=m_n,
        normal_pressure_angle=math.radians(spec.pair.normal_pressure_angle_deg),
        pinion=pinion,
        gear=gear,
        notes=tuple(notes),
        offset_residual_mm=float(residual),
        procedure=procedure,
    )

"""The generated design kernels (``generated/design_equations.py``), called by name.

``c`` is the design's constants by the paper's symbols (m_n, alpha_n, delta, E, N1, N2, x_t1, gamma1,
gamma2, beta1; radians and mm), from :func:`beveloid.design.solve.spec_constants`.
"""
from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np

from ..generated import design_equations as equations


def pair_kwargs(c: dict[str, Any]) -> dict[str, Any]:
    """The design kernels' pair and reference arguments, by name."""
    return dict(normal_module=c["m_n"], normal_pressure_angle=c["alpha_n"], pinion_teeth=c["N1"],
                gear_teeth=c["N2"], shaft_angle=c["delta"], pinion_profile_shift=c["x_t1"],
                pinion_cone_angle=c["gamma1"], gear_cone_angle=c["gamma2"], pinion_helix_angle=c["beta1"])


def direct_outputs(alpha_nw, c: dict[str, Any]) -> dict[str, Any]:
    """Every output of the direct design at alpha_nw, by the generated names."""
    with np.errstate(all="ignore"):
        return equations.direct_design(alpha_nw=alpha_nw, **pair_kwargs(c))._asdict()


def residual(alpha_nw, c: dict[str, Any]):
    """E(alpha_nw) - E and its derivative d/d alpha_nw (Eq 17)."""
    with np.errstate(all="ignore"):
        return equations.offset_residual(alpha_nw=alpha_nw, offset=c["E"], **pair_kwargs(c))


def deg_text(x: float) -> str:
    """An angle (rad) in degrees for a message."""
    return f"{math.degrees(x):.6g}"


def num_text(x: float) -> str:
    """A number for a message."""
    return f"{x:.6g}"


class MemberOutputs(NamedTuple):
    """One member's outputs of the direct/indirect design kernels, by name (radians, mm)."""

    helix_angle: float
    cone_angle: float
    transverse_angular_factor: float
    mounting_distance_mm: float
    working_mounting_distance_mm: float
    working_cone_angle: float
    working_helix_angle: float
    working_pitch_radius_mm: float
    reference_pitch_radius_mm: float
    transverse_pressure_angle_left: float
    transverse_pressure_angle_right: float
    working_transverse_pressure_angle_left: float
    working_transverse_pressure_angle_right: float
    fpd_angle_left: float
    fpd_angle_right: float
    cos_pitch_point_angle: float
    sin_pitch_point_angle: float


#: The kernels number a member's outputs (beta1 pinion, beta2 gear): each field's name without the number.
#: The one place that reads that numbering.
_KERNEL_STEMS = MemberOutputs(
    helix_angle="beta", cone_angle="gamma", transverse_angular_factor="xi_t", mounting_distance_mm="d",
    working_mounting_distance_mm="d_w", working_cone_angle="gamma_w", working_helix_angle="beta_w",
    working_pitch_radius_mm="r_w", reference_pitch_radius_mm="r", transverse_pressure_angle_left="alpha_PL",
    transverse_pressure_angle_right="alpha_PR", working_transverse_pressure_angle_left="alpha_PwL",
    working_transverse_pressure_angle_right="alpha_PwR", fpd_angle_left="xi_L", fpd_angle_right="xi_R",
    cos_pitch_point_angle="cos_theta", sin_pitch_point_angle="sin_theta")

#: member name -> its number in the kernels' outputs
MEMBER_NUMBER = {"pinion": 1, "gear": 2}


def member_outputs(q: dict[str, float], member: str) -> MemberOutputs:
    """The outputs of ``member`` ("pinion" or "gear") among the kernels' outputs ``q``."""
    number = MEMBER_NUMBER[member]
    return MemberOutputs(**{field: q[f"{stem}{number}"] for field, stem in _KERNEL_STEMS._asdict().items()})

"""The generated design kernels (``generated/design_equations.py``), called by name.

``c`` is the design's constants by the paper's symbols (m_n, alpha_n, delta, E, N1, N2, x_t1, gamma1,
gamma2, beta1; radians and mm), from :func:`beveloid.design.solve.spec_constants`.
"""
from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..generated import design_equations as equations
from ..generated import layouts


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


#: One member's outputs of the direct/indirect design kernels, by name (radians, mm): the generated record.
MemberOutputs = layouts.MemberDesignOutputs


def member_outputs(q: dict[str, float], member: str) -> MemberOutputs:
    """The outputs of ``member`` ("pinion" or "gear") among the kernels' outputs ``q``, by the
    generated map of which output fills which field (design_equations.MEMBER_OUTPUTS)."""
    return MemberOutputs.pack({field: q[name] for field, name in equations.MEMBER_OUTPUTS[member].items()})

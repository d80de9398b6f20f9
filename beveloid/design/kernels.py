"""The generated design kernels (``generated/design_equations.py``), called by name.

``c`` is the design's constants by the paper's symbols (m_n, alpha_n, delta, E, N1, N2, x_t1, gamma1,
gamma2, beta1; radians and mm; one array entry per design), from :func:`beveloid.design.solve.constants`.
"""
from __future__ import annotations

import math

import numpy as np

from ..generated import design_equations as equations
from ..generated import layouts


#: the constants' flag of one design evaluated at Python scalars (see :func:`single`)
SCALAR = "scalar_kernels"


def single(c: dict) -> bool:
    """One design whose kernels are evaluated at Python scalars: numpy's array and scalar evaluations of
    the same expression may differ in the last bit (a power, a square root), and :func:`beveloid.design.design`
    keeps the scalar bits it always had, while a chunk of designs gives each design the same bits
    whatever its neighbours (the array evaluation, also for a chunk of one)."""
    return bool(c.get(SCALAR))


def pair_kwargs(c: dict, idx=None, column: bool = False) -> dict:
    """The design kernels' pair and reference arguments (by name) of the designs idx, as (k,) or (k, 1);
    Python scalars for a :func:`single` design."""
    def pick(v):
        if single(c):
            return np.asarray(v).item()
        v = v if idx is None else v[idx]
        return v[:, None] if column else v
    return dict(normal_module=pick(c["m_n"]), normal_pressure_angle=pick(c["alpha_n"]),
                pinion_teeth=pick(c["N1"]), gear_teeth=pick(c["N2"]), shaft_angle=pick(c["delta"]),
                pinion_profile_shift=pick(c["x_t1"]), pinion_cone_angle=pick(c["gamma1"]),
                gear_cone_angle=pick(c["gamma2"]), pinion_helix_angle=pick(c["beta1"]))


def direct_outputs(alpha_nw, c: dict) -> dict:
    """Every output of the direct design at alpha_nw (one per design), by the generated names."""
    with np.errstate(all="ignore"):
        return {k: np.asarray(v, dtype=float)
                for k, v in equations.direct_design(alpha_nw=alpha_nw, **pair_kwargs(c))._asdict().items()}


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

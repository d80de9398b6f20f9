"""The direct design of many designs at once: the one implementation of the algorithm.

:func:`design_arrays` takes spec values by dotted key (one array entry per design), solves Eq 17 for
alpha_nw (``solve.py``), evaluates Eqs 12-27 (the generated kernels broadcast over the designs) and
runs the checks (``checks.py``), giving each design a named :class:`~beveloid.design.checks.Outcome`.
:func:`beveloid.design.design` is this at n = 1 (:func:`spec_values`), plus the one-line refusal
that explains a failed outcome; ``beveloid explore`` calls it on chunks of designs.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..names import Member
from ..spec import DesignSpec
from . import checks, solve
from .checks import Outcome
from .kernels import SCALAR, direct_outputs
from .members import DesignError

#: the spec values (dotted keys) the design reads
INPUT_KEYS = ("pair.normal_module_mm", "pair.normal_pressure_angle_deg", "pair.shaft_angle_deg", "pair.offset_mm",
              "pinion.teeth", "pinion.cone_angle_deg", "pinion.helix_angle_deg", "pinion.profile_shift",
              "gear.teeth", "gear.cone_angle_deg",
              *(f"{m}.{k}" for m in Member for k in ("face_width_mm", "addendum_coefficient",
                                                      "cutter_addendum_coefficient", "reference_section_offset_mm")))


class ArrayDesign(NamedTuple):
    """The direct design of n designs (radians, mm).

    ``outcome``: Outcome codes (n,); ``alpha_nw`` and ``offset_residual_mm`` (n,), nan without a root of
    Eq 17; ``q``: the generated direct_design outputs by name at alpha_nw (n,) -- also for designs that
    fail a later check (their numbers are what the check refused); ``roots``: every root found."""

    outcome: np.ndarray
    alpha_nw: np.ndarray
    offset_residual_mm: np.ndarray
    q: dict
    roots: solve.Roots
    constants: dict

    @property
    def ok(self) -> np.ndarray:
        return self.outcome == Outcome.OK

    def labels(self) -> np.ndarray:
        """The outcome of each design by name ("ok", "pointed_teeth", ...)."""
        return np.array(checks.LABELS, dtype=object)[self.outcome]


def spec_values(spec: DesignSpec) -> dict:
    """The design inputs of one spec as arrays of one (dotted key -> (1,) float)."""
    g1 = spec.pinion
    if g1.helix_angle_deg is None or g1.profile_shift is None:
        raise DesignError("pinion.helix_angle_deg and pinion.profile_shift are required for the direct design",
                          keys=("pinion.helix_angle_deg", "pinion.profile_shift"), source=spec.source)
    out = {}
    for key in INPUT_KEYS:
        section, name = key.split(".")
        out[key] = np.array([float(getattr(getattr(spec, section), name))])
    return out


def design_arrays(values: dict, scalar: bool = False) -> ArrayDesign:
    """The direct design of n designs given by spec values (dotted key -> (n,) float array; at least
    INPUT_KEYS).  ``scalar`` (one design): evaluate the kernels at Python scalars (kernels.single)."""
    c = solve.constants(values)
    if scalar:
        c[SCALAR] = True
    n = np.asarray(c["m_n"]).size
    outcome = np.zeros(n, dtype=np.int64)
    outcome[(c["gamma1"] == 0.0) | (c["gamma2"] == 0.0)] = Outcome.ZERO_CONE_ANGLE
    found = solve.roots(c, np.nonzero(outcome == Outcome.OK)[0])
    alpha, resid = solve.closest(found, n)
    outcome[(outcome == Outcome.OK) & ~np.isfinite(alpha)] = Outcome.NO_WORKING_PRESSURE_ANGLE
    q = direct_outputs(alpha, c)
    checks.check(values, q, alpha, outcome)
    return ArrayDesign(outcome, alpha, resid, q, found, c)

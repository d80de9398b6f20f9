"""The five assembly errors of Eq 34 as a user meets them: the one table of their TOML/JSON
keys, CLI flags, units, limits and descriptions, and the conversion to the generated kernels'
``layouts.AssemblyErrors`` (mm and rad, in the kernels' order).

The spec's ``[misalignment]`` section, the ``tca`` / ``sweep`` flags, the JSON ``errors``
objects and the sweep's ranges all read this table.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .generated.layouts import AssemblyErrors


@dataclass(frozen=True)
class AssemblyError:
    key: str  #: TOML / JSON key, in the user's unit (e.g. "vertical_deg")
    field: str  #: the generated layout's field (e.g. "vertical_rad")
    flag: str  #: CLI flag of tca (sweep uses flag + "-max")
    unit: str  #: "mm" or "deg"
    limit: float  #: |value| <= limit, in the user's unit
    description: str

    @property
    def to_layout(self) -> float:
        """Factor from the user's unit to the layout's (mm -> mm, deg -> rad)."""
        return math.pi / 180 if self.unit == "deg" else 1.0


ERRORS: tuple[AssemblyError, ...] = (
    AssemblyError("dx_mm", "dx_mm", "--dx", "mm", 10.0,
                  "gear offset error dx_q of Eq 34 (frame S_q of the aligned gear; x_q is the common perpendicular)"),
    AssemblyError("dy_mm", "dy_mm", "--dy", "mm", 10.0, "gear offset error dy_q of Eq 34 (frame S_q)"),
    AssemblyError("dz_mm", "dz_mm", "--dz", "mm", 10.0, "gear offset error dz_q of Eq 34 (frame S_q: along the gear axis)"),
    AssemblyError("vertical_deg", "vertical_rad", "--vertical", "deg", 5.0,
                  "angular error dgamma_v of Eq 34 (gear axis turned about y_q)"),
    AssemblyError("horizontal_deg", "horizontal_rad", "--horizontal", "deg", 5.0,
                  "angular error dgamma_h of Eq 34 (gear axis turned about x_q)"),
)
KEYS = tuple(e.key for e in ERRORS)
BY_KEY = {e.key: e for e in ERRORS}
#: Default half-widths of the uniform error ranges (the sweep's, explore's tolerance box), keyed and in
#: units as ERRORS
DEFAULT_RANGES = dict(zip(KEYS, (0.5, 0.5, 0.5, 0.2, 0.03)))
assert tuple(e.field for e in ERRORS) == AssemblyErrors._fields, "ERRORS must follow the generated layout"


def to_layout(values) -> np.ndarray:
    """{key: value in the user's unit} (or an object with those attributes) -> (5,) mm/rad array."""
    get = values.get if isinstance(values, dict) else (lambda k, d=0.0: getattr(values, k, d))
    return np.asarray(AssemblyErrors(**{e.field: float(get(e.key, 0.0)) * e.to_layout for e in ERRORS}), dtype=float)


def from_layout(vector) -> dict:
    """(5,) mm/rad array -> {key: value in the user's unit}."""
    v = AssemblyErrors(*(float(x) for x in vector))
    return {e.key: getattr(v, e.field) / e.to_layout for e in ERRORS}


def label(values) -> str:
    """'dx=0.5 mm, ..., horizontal=0.01 deg' for titles and tables."""
    d = values if isinstance(values, dict) else {k: getattr(values, k) for k in KEYS}
    return ", ".join(f"{e.key.rsplit('_', 1)[0]}={d[e.key]:g} {e.unit}" for e in ERRORS)

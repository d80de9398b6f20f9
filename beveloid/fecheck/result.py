"""What :func:`beveloid.fecheck.analyze` returns: the FE check at one position beside the LTCA's
numbers there, a deep-frozen :class:`beveloid.result.Result` (its arrays read-only, its mappings
:class:`beveloid.result.FrozenMap`), with the JSON of the contract (docs/fe_check.md) from
:meth:`CheckResult.to_json`, which needs nothing passed back in."""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any
from typing import Mapping

import numpy as np

from ..result import Frozen, Result, thaw

__all__ = ["CheckResult", "ContactNumbers", "ROOT_STRESS_AGREEMENT", "root_stress_agreement"]

#: the two FE models' root stresses agree when within this share of each other (issue 57.5: the rating's
#: local S_F rests on the LTCA's FE tooth; CalculiX's full-contact sectors check it)
ROOT_STRESS_AGREEMENT = 0.10


def root_stress_agreement(calculix: "ContactNumbers", ltca: "ContactNumbers") -> dict:
    """{member: {"calculix_mpa", "ltca_mpa", "ratio" (calculix / ltca), "agrees"}} of the largest root
    stresses at the checked position; null ratio and agreement where either is missing."""
    out = {}
    for m, c in calculix.root_stress_max_mpa.items():
        c, l = _num(c), _num(ltca.root_stress_max_mpa.get(m))
        ratio = None if c is None or not l else c / l
        out[m] = {"calculix_mpa": c, "ltca_mpa": l, "ratio": ratio,
                  "agrees": None if ratio is None else bool(abs(ratio - 1.0) <= ROOT_STRESS_AGREEMENT)}
    return out


def _num(v) -> float | None:
    """A JSON number: None for a missing or non-finite value."""
    return float(v) if v is not None and math.isfinite(v) else None


def _floats(values) -> np.ndarray:
    """A float array of ``values`` (nested sequences too), NaN where a value is None."""
    a = np.array(values, dtype=object)
    return np.where(np.equal(a, None), np.nan, a).astype(float)


@dataclass(frozen=True, eq=False)
class ContactNumbers(Frozen):
    """One side's numbers at the position (CalculiX's or the LTCA's), per tooth pair (P,) in the LTCA's
    order; NaN where a number is missing (a pair outside the sectors, a root stress without an FE tooth)."""

    pair_normal_load_n: np.ndarray  # (P,)
    pair_max_pressure_mpa: np.ndarray  # (P,)
    contact_area_mm2: np.ndarray  # (P,)
    loaded_transmission_error_urad: float
    root_stress_max_mpa: Mapping[str, float]  # {member: MPa}
    moment_about_pinion_axis_nm: float

    @classmethod
    def of(cls, pair_normal_load_n, pair_max_pressure_mpa, contact_area_mm2, loaded_transmission_error_urad,
           root_stress_max_mpa: dict, moment_about_pinion_axis_nm) -> "ContactNumbers":
        """From sequences and numbers (None for a missing one)."""
        missing = lambda v: math.nan if v is None else float(v)  # noqa: E731
        return cls(_floats(pair_normal_load_n), _floats(pair_max_pressure_mpa), _floats(contact_area_mm2),
                   missing(loaded_transmission_error_urad),
                   {m: missing(v) for m, v in root_stress_max_mpa.items()},
                   missing(moment_about_pinion_axis_nm))

    def to_json(self) -> dict:
        return {"pair_normal_load_n": [_num(v) for v in self.pair_normal_load_n],
                "pair_max_pressure_mpa": [_num(v) for v in self.pair_max_pressure_mpa],
                "contact_area_mm2": [_num(v) for v in self.contact_area_mm2],
                "loaded_transmission_error_urad": _num(self.loaded_transmission_error_urad),
                "root_stress_max_mpa": {m: _num(v) for m, v in self.root_stress_max_mpa.items()},
                "moment_about_pinion_axis_nm": _num(self.moment_about_pinion_axis_nm)}


@dataclass(frozen=True, eq=False)
class CheckResult(Result):
    """The FE check of ``pair`` under ``load`` (an ``ltca.LoadCase``) with ``options`` (a
    :class:`beveloid.fecheck.Options`) at the LTCA's position ``position``: CalculiX's numbers and the LTCA's
    side by side, the run's sizes and times, the files kept, the notes."""

    calculix_version: str | None
    position: int
    pinion_angle_rad: float
    ltca_tooth_model: str
    tooth_pairs: tuple
    unloaded_transmission_error_urad: float
    elements: int
    dof: int
    calculix_wall_s: float
    calculix_cpu_s: float
    mesh_s: float
    calculix: ContactNumbers
    ltca: ContactNumbers
    files: Mapping[str, str]  # {"deck", "frd", "dat", "vtu": path}; empty without out_dir
    notes: tuple
    ltca_hertz_max_pressure_mpa: np.ndarray  # (P,)
    ltca_patch_semi_axes_mm: np.ndarray  # (P, 2)
    #: per loaded pair its refinement strip ({"tooth_pair", "semi_axes_mm", "size_mm", element sizes});
    #: None: not refined
    local_refinement: tuple | None
    load: Any = field(default=None, kw_only=True, repr=False)  # the ltca.LoadCase

    def __post_init__(self):
        for name in ("ltca_hertz_max_pressure_mpa", "ltca_patch_semi_axes_mm"):
            object.__setattr__(self, name, _floats(getattr(self, name)))
        super().__post_init__()

    def to_json(self) -> dict:
        """The JSON of ``beveloid fe-check --json`` (docs/fe_check.md)."""
        o = self.options
        return {"calculix_version": self.calculix_version, "position": self.position,
                "pinion_angle_rad": self.pinion_angle_rad, "torque_nm": self.load.torque_nm, "flank": o.flank,
                "ltca_tooth_model": self.ltca_tooth_model, "refinement": o.refinement,
                "tooth_pairs": list(self.tooth_pairs),
                "unloaded_transmission_error_urad": self.unloaded_transmission_error_urad,
                "elements": self.elements, "dof": self.dof, "calculix_wall_s": self.calculix_wall_s,
                "calculix_cpu_s": self.calculix_cpu_s, "mesh_s": self.mesh_s,
                "calculix": self.calculix.to_json(), "ltca": self.ltca.to_json(),
                "root_stress_agreement": root_stress_agreement(self.calculix, self.ltca), "files": dict(self.files),
                "notes": list(self.notes),
                "ltca_hertz_max_pressure_mpa": [_num(v) for v in self.ltca_hertz_max_pressure_mpa],
                "ltca_patch_semi_axes_mm": [[_num(v) for v in ab] for ab in self.ltca_patch_semi_axes_mm],
                "local_refinement": thaw(self.local_refinement)}

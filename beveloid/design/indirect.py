"""The indirect design (second chart of Fig. 7): reference data from working data."""
from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping

import numpy as np

from ..spec import DesignSpec, SpecError, spec_from_dict, spec_to_dict
from .direct import finish
from .kernels import deg_text, equations
from .members import DesignError, DesignResult

_INDIRECT_IGNORED = {
    "pair": {"offset_mm": 1.0},
    "pinion": {"cone_angle_deg": 1.0, "helix_angle_deg": 0.0},
    "gear": {"cone_angle_deg": 1.0},
}


def _as_spec(spec_like: DesignSpec | Mapping) -> DesignSpec:
    if isinstance(spec_like, DesignSpec):
        return spec_like
    if isinstance(spec_like, Mapping):
        data = {k: (dict(v) if isinstance(v, Mapping) else v) for k, v in spec_like.items()}
        for section, keys in _INDIRECT_IGNORED.items():
            sec = data.get(section)
            if isinstance(sec, dict):
                for key, placeholder in keys.items():
                    sec.setdefault(key, placeholder)
        return spec_from_dict(data)
    raise TypeError(f"indirect_design() needs a DesignSpec or a dict, not {type(spec_like).__name__}")


def indirect_design(spec_like: DesignSpec | Mapping, alpha_nw: float, pinion_working_cone_angle: float,
                    gear_working_cone_angle: float, pinion_working_helix_angle: float) -> DesignResult:
    """Indirect design (Fig. 7, second chart): reference data from working data.

    ``spec_like`` (a :class:`DesignSpec` or a spec dict) supplies m_n, alpha_n, delta, N1, N2,
    x_t1 and the blank data; its offset, pinion cone/helix angles and gear cone angle are
    ignored.  The four working quantities are in radians (helix signed, + right hand).
    Returns a :class:`DesignResult` whose ``spec`` carries the computed gamma1, gamma2, beta1 and E.
    """
    spec = _as_spec(spec_like)
    src = spec.source
    p, g1 = spec.pair, spec.pinion
    if g1.profile_shift is None:
        raise DesignError("pinion.profile_shift is required for the indirect design",
                          keys=("pinion.profile_shift",), source=src)
    args = {"alpha_nw": alpha_nw, "pinion_working_cone_angle": pinion_working_cone_angle,
            "gear_working_cone_angle": gear_working_cone_angle,
            "pinion_working_helix_angle": pinion_working_helix_angle}
    for name, value in args.items():
        if not isinstance(value, (int, float, np.floating, np.integer)) or not math.isfinite(float(value)):
            raise DesignError(f"{name} = {value!r}: must be a finite angle in radians", keys=(name,), source=src)
    alpha_nw = float(alpha_nw)
    gw1, gw2, bw1 = float(pinion_working_cone_angle), float(gear_working_cone_angle), float(pinion_working_helix_angle)
    if not 0.0 < alpha_nw < math.pi / 2:
        raise DesignError(f"alpha_nw = {alpha_nw!r} rad: must be between 0 and pi/2", keys=("alpha_nw",), source=src)
    for name, g in (("pinion_working_cone_angle", gw1), ("gear_working_cone_angle", gw2)):
        if g == 0.0 or abs(g) >= math.pi / 2:
            raise DesignError(f"{name} = {g!r} rad: must be non-zero with |value| < pi/2 (a zero cone angle puts the"
                              f" cone apex at infinity)", keys=(name,), source=src)
    if abs(bw1) >= math.pi / 2:
        raise DesignError(f"pinion_working_helix_angle = {bw1!r} rad: |value| must be < pi/2",
                          keys=("pinion_working_helix_angle",), source=src)
    alpha_n = math.radians(p.normal_pressure_angle_deg)
    with np.errstate(all="ignore"):
        out = equations.indirect_design(
            alpha_nw=alpha_nw, normal_module=float(p.normal_module_mm), normal_pressure_angle=alpha_n,
            pinion_teeth=int(g1.teeth), gear_teeth=int(spec.gear.teeth), shaft_angle=math.radians(p.shaft_angle_deg),
            pinion_profile_shift=float(g1.profile_shift), pinion_working_cone_angle=gw1, gear_working_cone_angle=gw2,
            pinion_working_helix_angle=bw1)
    q = {k: float(v) for k, v in out._asdict().items()}
    for member, key, gw in (("pinion", "gamma1", gw1), ("gear", "gamma2", gw2)):
        if not math.isfinite(q[key]):
            name = f"{member}_working_cone_angle"
            raise DesignError(
                f"{name} = {deg_text(gw)} deg: Eq 25 has no reference cone angle (sin gamma = sin gamma_w sin alpha_nw /"
                f" sin alpha_n > 1 with alpha_nw = {deg_text(alpha_nw)} deg); reduce |{name}| or alpha_nw",
                keys=(name,), source=src)
    if not math.isfinite(q["beta_w2"]):
        raise DesignError(
            f"pair.shaft_angle_deg = {p.shaft_angle_deg!r}: the pitch cones cannot touch (sin^2 delta < sin^2 gw1 +"
            f" sin^2 gw2 + 2 sin gw1 sin gw2 cos delta with gamma_w1 = {deg_text(gw1)}, gamma_w2 = {deg_text(gw2)} deg);"
            f" increase the shaft angle or reduce the working cone angles",
            keys=("pair.shaft_angle_deg", "pinion_working_cone_angle", "gear_working_cone_angle"), source=src)
    if not math.isfinite(q["beta1"]):
        raise DesignError(
            f"pinion_working_helix_angle = {deg_text(bw1)} deg: Eq 26 has no reference helix angle"
            f" (|sin beta1| > 1); reduce |pinion_working_helix_angle|",
            keys=("pinion_working_helix_angle",), source=src)
    new_pair = dataclasses.replace(p, offset_mm=q["E"])
    new_pinion = dataclasses.replace(g1, cone_angle_deg=math.degrees(q["gamma1"]),
                                     helix_angle_deg=math.degrees(q["beta1"]))
    new_gear = dataclasses.replace(spec.gear, cone_angle_deg=math.degrees(q["gamma2"]))
    new_spec = dataclasses.replace(spec, pair=new_pair, pinion=new_pinion, gear=new_gear)
    try:  # the computed reference data must themselves form a valid spec
        spec_from_dict(spec_to_dict(new_spec))
    except SpecError as err:
        raise DesignError(f"the indirect design gives {err.detail}; change the working data",
                          keys=((err.key,) if err.key else ()), source=src) from None
    return finish(new_spec, q, alpha_nw, residual=0.0, notes=[], procedure="indirect")  # its offset: q["E"]

"""The oil: viscosity at the oil temperature (ASTM D341), density, pressure-viscosity coefficient and
the factors of the friction and scuffing laws, from ``[lubricant]`` (docs/tribology.md, "The oil").

A grade (``iso_vg``, ISO 3448: the kinematic viscosity at 40 C) with a ``base_oil`` gives the 100 C
viscosity from the base oil's typical Walther slope; explicit ``kinematic_viscosity_40_mm2_s`` and
``kinematic_viscosity_100_mm2_s`` replace both; ``kinematic_viscosity_mm2_s`` (measured at the oil
temperature) replaces the interpolation.  Between and beyond 40 and 100 C the viscosity follows
ASTM D341's Walther line, log10 log10(nu + 0.7) = A - B log10(T / K).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

#: ISO 3448 viscosity grades (mm^2/s at 40 C)
ISO_VG = (2, 3, 5, 7, 10, 15, 22, 32, 46, 68, 100, 150, 220, 320, 460, 680, 1000, 1500, 2200, 3200)
KELVIN = 273.15
#: the oil temperature's upper limit (C): beyond it the laws of docs/tribology.md are not fitted
MAX_TEMPERATURE_C = 200.0


@dataclass(frozen=True)
class BaseOil:
    """Representative defaults of a base oil (docs/tribology.md: where each comes from)."""

    walther_slope: float  #: B of ASTM D341 (from the 40 and 100 C viscosities of a typical VG 32 oil)
    density_15_kg_m3: float
    pour_point_c: float
    lubricant_factor_xl: float  #: ISO/TR 14179-2's X_L
    pressure_viscosity_38_1_per_gpa: float  #: alpha at 38 C (ISO/TS 6336-22's table form)


#: typical VG 32 oils: mineral VI ~100 (nu_100 5.4), PAO and ester VI ~140 (6.0), polyglycol VI ~190 (6.7)
BASE_OILS = {
    "mineral": BaseOil(3.746, 885.0, -15.0, 1.0, 21.0),
    "pao": BaseOil(3.458, 845.0, -50.0, 0.8, 16.0),
    "ester": BaseOil(3.458, 920.0, -45.0, 1.0, 15.0),
    "polyglycol": BaseOil(3.167, 1010.0, -40.0, 0.7, 13.0),
}


class LubricantError(ValueError):
    """One line naming the key (``key``: dotted)."""

    def __init__(self, message, key):
        super().__init__(message)
        self.key = key


def walther(nu_mm2_s):
    return math.log10(math.log10(nu_mm2_s + 0.7))


def viscosity_from_walther(nu_a, t_a_c, nu_b, t_b_c, t_c):
    """ASTM D341: the kinematic viscosity (mm^2/s) at t_c through (t_a_c, nu_a) and (t_b_c, nu_b)."""
    xa, xb, x = (math.log10(t + KELVIN) for t in (t_a_c, t_b_c, t_c))
    w = walther(nu_a) + (walther(nu_b) - walther(nu_a)) * (x - xa) / (xb - xa)
    return 10.0 ** (10.0 ** w) - 0.7


def nu100_from_slope(nu40, slope):
    """The 100 C viscosity of a Walther line of slope B through (40 C, nu40)."""
    w = walther(nu40) - slope * (math.log10(100 + KELVIN) - math.log10(40 + KELVIN))
    return 10.0 ** (10.0 ** w) - 0.7


@dataclass(frozen=True)
class Lubricant:
    """The oil at its temperature (SI where not named otherwise)."""

    base_oil: str
    temperature_c: float
    kinematic_viscosity_mm2_s: float  #: at temperature_c
    density_kg_m3: float  #: at temperature_c
    pressure_viscosity_1_per_gpa: float  #: at temperature_c
    lubricant_factor_xl: float
    fzg_load_stage: int | None = None
    friction_coefficient: float | None = None  #: fixed: overrides the friction law

    @property
    def dynamic_viscosity_mpa_s(self) -> float:
        return self.kinematic_viscosity_mm2_s * self.density_kg_m3 * 1e-3

    @property
    def dynamic_viscosity_pa_s(self) -> float:
        return self.dynamic_viscosity_mpa_s * 1e-3

    @property
    def pressure_viscosity_1_per_pa(self) -> float:
        return self.pressure_viscosity_1_per_gpa * 1e-9

    @classmethod
    def from_spec(cls, lub) -> "Lubricant":
        """From a validated :class:`beveloid.spec.model.LubricantSpec` (``lub.given``)."""
        base = BASE_OILS[lub.base_oil]
        t = lub.temperature_c
        if lub.kinematic_viscosity_mm2_s is not None:
            nu = lub.kinematic_viscosity_mm2_s
        else:
            nu40 = lub.kinematic_viscosity_40_mm2_s if lub.kinematic_viscosity_40_mm2_s is not None else float(lub.iso_vg)
            nu100 = lub.kinematic_viscosity_100_mm2_s
            if nu100 is None:
                nu100 = nu100_from_slope(nu40, base.walther_slope)
            nu = viscosity_from_walther(nu40, 40.0, nu100, 100.0, t)
        rho15 = lub.density_15_kg_m3 if lub.density_15_kg_m3 is not None else base.density_15_kg_m3
        alpha = lub.pressure_viscosity_coefficient_1_per_gpa
        if alpha is None:  # ISO/TS 6336-22's temperature correction of alpha_38
            alpha = base.pressure_viscosity_38_1_per_gpa * (1 + 516 * (1 / (t + KELVIN) - 1 / 311.0))
        xl = lub.lubricant_factor_xl if lub.lubricant_factor_xl is not None else base.lubricant_factor_xl
        return cls(lub.base_oil, t, nu, density_at(rho15, t), alpha, xl, lub.fzg_load_stage, lub.friction_coefficient)


def density_at(rho15_kg_m3, t_c):
    """A mineral oil's typical thermal expansion, 0.7 kg/m^3 less per K above 15 C (docs/tribology.md)."""
    return rho15_kg_m3 - 0.7 * (t_c - 15.0)


def check_spec_values(values) -> None:
    """The rules between [lubricant]'s keys and the members' roughness (spec validation's cross check);
    raises :class:`LubricantError` (one line naming the key)."""
    lub = values["lubricant"]
    oil_keys = ("iso_vg", "kinematic_viscosity_40_mm2_s", "kinematic_viscosity_100_mm2_s", "kinematic_viscosity_mm2_s")
    given = any(lub[k] is not None for k in oil_keys)
    others = [k for k, v in lub.items() if v is not None and k not in oil_keys and k != "base_oil"]
    if not given:
        if others:
            raise LubricantError(f"lubricant.{others[0]} = {lub[others[0]]}: needs an oil: lubricant.iso_vg (an ISO "
                                 "3448 grade) or lubricant.kinematic_viscosity_40_mm2_s and _100_mm2_s",
                                 key=f"lubricant.{others[0]}")
        return
    vg = lub["iso_vg"]
    if vg is not None and vg not in ISO_VG:
        raise LubricantError(f"lubricant.iso_vg = {vg}: not an ISO 3448 grade; valid grades are "
                             f"{', '.join(map(str, ISO_VG))}", key="lubricant.iso_vg")
    nu40, nu100 = lub["kinematic_viscosity_40_mm2_s"], lub["kinematic_viscosity_100_mm2_s"]
    if lub["kinematic_viscosity_mm2_s"] is None and vg is None and (nu40 is None or nu100 is None):
        missing = "kinematic_viscosity_100_mm2_s" if nu100 is None else "kinematic_viscosity_40_mm2_s"
        raise LubricantError(f"lubricant.{missing}: missing; give both viscosities (40 and 100 C) or iso_vg",
                             key=f"lubricant.{missing}")
    if nu40 is not None and nu100 is not None and nu100 >= nu40:
        raise LubricantError(f"lubricant.kinematic_viscosity_100_mm2_s = {nu100:g}: must be below the 40 C viscosity "
                             f"({nu40:g} mm^2/s)", key="lubricant.kinematic_viscosity_100_mm2_s")
    t = lub["temperature_c"]
    if t is None:
        raise LubricantError("lubricant.temperature_c: missing; the oil temperature (C) is needed with an oil",
                             key="lubricant.temperature_c")
    pour = lub["pour_point_c"] if lub["pour_point_c"] is not None else BASE_OILS[lub["base_oil"]].pour_point_c
    if t <= pour:
        raise LubricantError(f"lubricant.temperature_c = {t:g}: must be above the oil's pour point ({pour:g} C) and at "
                             f"most {MAX_TEMPERATURE_C:g} C", key="lubricant.temperature_c")
    for member in ("pinion", "gear"):
        if values[member].get("roughness_ra_um") is None:
            raise LubricantError(f"{member}.roughness_ra_um: missing; the flank roughness Ra (um, > 0) is needed with "
                                 "[lubricant]", key=f"{member}.roughness_ra_um")

"""The factors of the permissible stresses besides the life factors (docs/rating.md 4.4).

ISO 6336-2's lubricant, velocity and roughness factors Z_L, Z_v, Z_R of the permissible contact stress
and ISO 6336-3's size factor Y_X and relative surface factor Y_RrelT of the permissible root stress,
per member, each with its inputs (the JSON's ``strength_factors``):

* Z_L from the oil's kinematic viscosity at 40 C (``[lubricant] kinematic_viscosity_40_mm2_s``, else
  its ISO VG grade, which is nu_40 by definition) and C_ZL of the member's sigma_Hlim;
* Z_v from the pitch line velocity of the pinion's middle section (the v of K_v method B) at
  ``[rating] pinion_speed_rpm``;
* Z_R from the mean R_z of the two members' flanks (``roughness_rz_um``, else 6 ``roughness_ra_um``),
  referred to rho_red at the pitch point of the member's middle virtual cylindrical pair;
* Y_X from the rack's normal module and the member's material group;
* Y_RrelT from the member's ``root_roughness_rz_um``.

A factor whose input is missing is 1 and says why (``why``); the verdict lists those as assumptions.
The values are ISO's long-life (reference) values; :meth:`MemberStrength.contact_at` and
:meth:`MemberStrength.root_at` interpolate them to 1 (ISO's static value) over the life curve's
limited-life branch, as ISO 6336-2/-3 method B interpolate the whole permissible stress.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ..names import MEMBERS
from . import iso6336, materials
from .virtual import mate_gear, section_gear

__all__ = ["RA_TO_RZ", "StrengthFactor", "MemberStrength", "strength_factors", "life_weight"]

#: R_z = 6 R_a: the approximation of DIN 3991 (and of FVA's programs) where only R_a is given
RA_TO_RZ = 6.0


@dataclass(frozen=True)
class StrengthFactor:
    """One factor: its long-life value (1 where not computed), its inputs, and why it is 1 if it is."""

    name: str
    value: float
    inputs: dict
    why: str = ""  # "" where computed; else the missing input, in words

    @property
    def computed(self) -> bool:
        return not self.why

    def as_json(self) -> dict:
        return {"value": float(self.value), "computed": self.computed, "inputs": dict(self.inputs),
                "why_not_computed": self.why or None}


@dataclass(frozen=True)
class MemberStrength:
    """A member's Z_L, Z_v, Z_R (contact) and Y_X, Y_RrelT (root), long-life values."""

    contact: tuple  # (Z_L, Z_v, Z_R) StrengthFactor
    root: tuple  # (Y_X, Y_RrelT) StrengthFactor

    @property
    def contact_product(self) -> float:
        return math.prod(f.value for f in self.contact)

    @property
    def root_product(self) -> float:
        return math.prod(f.value for f in self.root)

    def contact_at(self, z_nt_points, cycles) -> float:
        """Z_L Z_v Z_R at ``cycles`` load cycles: :func:`life_weight` of the Z_NT curve."""
        return self.contact_product ** life_weight(z_nt_points, cycles)

    def root_at(self, y_nt_points, cycles) -> float:
        """Y_X Y_RrelT at ``cycles`` load cycles: :func:`life_weight` of the Y_NT curve."""
        return self.root_product ** life_weight(y_nt_points, cycles)

    def as_json(self) -> dict:
        return {f.name: f.as_json() for f in self.contact + self.root}


def life_weight(points, cycles) -> float:
    """How much of a long-life factor applies at ``cycles`` (ISO 6336-2/-3 method B interpolate the
    permissible stress log-log between its static value, where these factors are 1, and its reference
    value, where they are whole): 0 up to the life curve's static point, 1 from its knee (the second
    point, where the life factor reaches 1) on, log(N/N_static)/log(N_knee/N_static) between; 1 for
    long life (``cycles`` None)."""
    if cycles is None:
        return 1.0
    (n_static, _), (n_knee, _) = points[0], points[1]
    if cycles <= n_static:
        return 0.0
    if cycles >= n_knee:
        return 1.0
    return math.log(cycles / n_static) / math.log(n_knee / n_static)


def _nu_40(lub) -> tuple:
    """(nu_40 mm^2/s or None, where from)."""
    if lub.kinematic_viscosity_40_mm2_s is not None:
        return float(lub.kinematic_viscosity_40_mm2_s), "lubricant.kinematic_viscosity_40_mm2_s"
    if lub.iso_vg is not None:
        return float(lub.iso_vg), f"lubricant.iso_vg = {lub.iso_vg} (nu_40 of the grade)"
    return None, None


def flank_rz_um(member_spec) -> tuple:
    """(R_z of the flanks in um or None, where from): ``roughness_rz_um``, else :data:`RA_TO_RZ` R_a."""
    if member_spec.roughness_rz_um is not None:
        return float(member_spec.roughness_rz_um), "roughness_rz_um"
    if member_spec.roughness_ra_um is not None:
        return RA_TO_RZ * float(member_spec.roughness_ra_um), f"{RA_TO_RZ:g} roughness_ra_um (DIN 3991)"
    return None, None


def pitch_point_radii_mm(pair: iso6336.CylindricalPair) -> tuple:
    """(rho_1, rho_2, rho_red) in mm of a virtual cylindrical pair at its pitch point, in the transverse
    plane: rho_i = d_bi tan(alpha_wt) / 2, rho_red = rho_1 rho_2 / (rho_1 + rho_2) (ISO 6336-2)."""
    t = math.tan(pair.working_pressure_angle)
    r1, r2 = pair.gear.base_diameter_mm * t / 2, pair.mate.base_diameter_mm * t / 2
    return r1, r2, r1 * r2 / (r1 + r2)


def pitch_line_velocity_m_s(geometry, flank: str, pinion_speed_rpm: float) -> tuple:
    """(v in m/s, d_1 in mm): the pinion's middle virtual gear's reference circle at the pinion speed
    (the v of K_v method B, rating.analysis.dynamic_factor)."""
    d1 = section_gear(geometry, "pinion", 0.0, flank).gear.reference_diameter_mm
    return math.pi * d1 * pinion_speed_rpm / 60000.0, d1


def strength_factors(spec, geometry, flank: str, contact_limit_mpa: dict, material: dict) -> dict:
    """member -> :class:`MemberStrength` of a validated spec: ``contact_limit_mpa`` the members'
    sigma_Hlim, ``material`` their type names (``Factors``)."""
    nu40, nu40_from = _nu_40(spec.lubricant)
    n1 = spec.rating.pinion_speed_rpm
    v, d1 = pitch_line_velocity_m_s(geometry, flank, n1) if n1 is not None else (None, None)
    rz = {m: flank_rz_um(getattr(spec, m)) for m in MEMBERS}
    out = {}
    for member in MEMBERS:
        s_hlim = float(contact_limit_mpa[member])
        c_zl, c_zr = iso6336.lubricant_constant(s_hlim), iso6336.roughness_constant(s_hlim)
        if nu40 is None:
            z_l = StrengthFactor("Z_L", 1.0, {"sigma_Hlim_mpa": s_hlim},
                                 "no oil viscosity at 40 C: [lubricant] iso_vg or kinematic_viscosity_40_mm2_s")
        else:
            z_l = StrengthFactor("Z_L", iso6336.lubricant_factor(c_zl, nu40),
                                 {"nu_40_mm2_s": nu40, "nu_40_from": nu40_from, "sigma_Hlim_mpa": s_hlim, "C_ZL": c_zl})
        if v is None:
            z_v = StrengthFactor("Z_v", 1.0, {"sigma_Hlim_mpa": s_hlim}, "no [rating] pinion_speed_rpm")
        else:
            z_v = StrengthFactor("Z_v", iso6336.velocity_factor(c_zl, v),
                                 {"pitch_line_velocity_m_s": v, "pinion_reference_diameter_mm": d1,
                                  "pinion_speed_rpm": float(n1), "sigma_Hlim_mpa": s_hlim, "C_Zv": c_zl + 0.02})
        missing = [m for m in MEMBERS if rz[m][0] is None]
        if missing:
            z_r = StrengthFactor("Z_R", 1.0, {"sigma_Hlim_mpa": s_hlim},
                                 f"no flank roughness of the {' and the '.join(missing)}: roughness_rz_um or "
                                 "roughness_ra_um")
        else:
            sec = section_gear(geometry, member, 0.0, flank)
            virtual = iso6336.CylindricalPair(sec.gear, mate_gear(geometry, sec, flank), 1.0)
            rho1, rho2, rho_red = pitch_point_radii_mm(virtual)
            rz_mean = (rz["pinion"][0] + rz["gear"][0]) / 2
            value, rz10 = iso6336.roughness_factor(c_zr, rz_mean, rho_red)
            z_r = StrengthFactor("Z_R", value, {
                "R_z_pinion_um": rz["pinion"][0], "R_z_pinion_from": rz["pinion"][1], "R_z_gear_um": rz["gear"][0],
                "R_z_gear_from": rz["gear"][1], "R_z_um": rz_mean, "rho_1_mm": rho1, "rho_2_mm": rho2,
                "rho_red_mm": rho_red, "R_z10_um": rz10, "sigma_Hlim_mpa": s_hlim, "C_ZR": c_zr})
        mat = materials.MATERIALS[material[member]]
        m_n = float(geometry.normal_module_mm)
        y_x = StrengthFactor("Y_X", iso6336.size_factor_bending(mat.size_group, m_n),
                             {"normal_module_mm": m_n, "group": mat.size_group})
        root_rz = getattr(spec, member).root_roughness_rz_um
        if root_rz is None:
            y_r = StrengthFactor("Y_RrelT", 1.0, {"group": mat.surface_group},
                                 "no root_roughness_rz_um: taken as the reference test gear's root, R_z about 10 um")
        else:
            y_r = StrengthFactor("Y_RrelT", iso6336.relative_surface_factor(mat.surface_group, float(root_rz)),
                                 {"root_R_z_um": float(root_rz), "group": mat.surface_group})
        out[member] = MemberStrength((z_l, z_v, z_r), (y_x, y_r))
    return out

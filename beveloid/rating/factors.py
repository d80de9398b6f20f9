"""Load factors, life factors and permissible stresses of the rating (docs/rating.md, 4).

What is modelled and what is left at 1 is said here once; ``notes(...)`` repeats it in the output.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

from . import materials
from .iso6336 import ISO_EDITION
from .materials import life_factor

__all__ = ["Factors", "Y_ST", "face_factor_exponent", "life_factor"]

#: stress correction factor of the reference test gear (ISO 6336-3: sigma_FE = sigma_Flim Y_ST)
Y_ST = 2.0


def face_factor_exponent(face_width_mm: float, tooth_depth_mm: float) -> float:
    """N_F = (b/h)^2 / (1 + b/h + (b/h)^2) of ISO 6336-1:2019 (K_Fbeta = K_Hbeta^N_F), b/h at least 3
    (the caller passes the smaller b/h of the pair)."""
    bh = max(face_width_mm / tooth_depth_mm, 3.0)
    return bh ** 2 / (1 + bh + bh ** 2)


@dataclass(frozen=True)
class Factors:
    """The rating's factors from the spec's [rating] and [material] (limits in MPa)."""

    K_A: float
    K_v: float
    S_Fmin: float
    S_Hmin: float
    root_limit_mpa: dict  # member -> sigma_Flim
    contact_limit_mpa: dict  # member -> sigma_Hlim
    cycles: dict  # member -> load cycles N_L, or None (no speed / life given)
    material: dict = field(default_factory=dict)  # member -> {"type", "quality", "hardness", "limits_from"}
    K_v_source: str = "user"  # "user" (rating.K_v), "method B" (computed), "static" (no speed: 1), "not computed"
    #: member -> strength.MemberStrength (Z_L, Z_v, Z_R, Y_X, Y_RrelT; :meth:`with_strength`); empty: all 1
    strength: dict = field(default_factory=dict)

    @classmethod
    def from_spec(cls, spec) -> "Factors":
        r, m = spec.rating, spec.material
        n1 = None
        if r.pinion_speed_rpm is not None and r.life_hours is not None:
            n1 = 60.0 * r.pinion_speed_rpm * r.life_hours
        ratio = spec.pinion.teeth / spec.gear.teeth
        root, contact, mats = {}, {}, {}
        for member in ("pinion", "gear"):
            kind, quality = getattr(m, f"{member}_material"), getattr(m, f"{member}_material_quality")
            hardness = materials.check_member(member, kind, quality, getattr(m, f"{member}_surface_hardness_hv"),
                                              getattr(m, f"{member}_surface_hardness_hbw"))
            iso_h, iso_f = materials.limits_mpa(kind, quality, hardness)
            user_h = getattr(m, f"{member}_contact_stress_limit_mpa")
            user_f = getattr(m, f"{member}_root_stress_limit_mpa")
            contact[member] = iso_h if user_h is None else user_h
            root[member] = iso_f if user_f is None else user_f
            unit = materials.MATERIALS[kind].hardness_unit
            mats[member] = {"type": kind, "iso": materials.MATERIALS[kind].iso, "quality": quality,
                            f"surface_hardness_{unit or 'hv'}": hardness,
                            "sigma_Hlim_mpa": contact[member], "sigma_Flim_mpa": root[member],
                            "sigma_Hlim_from": "ISO 6336-5" if user_h is None else "user",
                            "sigma_Flim_from": "ISO 6336-5" if user_f is None else "user"}
        if r.K_v is not None:
            k_v, source = r.K_v, "user"
        elif r.pinion_speed_rpm is not None:
            k_v, source = math.nan, "method B"  # set by the analysis from the loaded contact
        else:
            k_v, source = 1.0, "static"
        return cls(r.K_A, k_v, r.S_Fmin, r.S_Hmin, root, contact,
                   {"pinion": n1, "gear": None if n1 is None else n1 * ratio}, mats, source)

    def with_strength(self, spec, geometry, flank: str) -> "Factors":
        """These factors with each member's Z_L, Z_v, Z_R, Y_X and Y_RrelT (``strength.strength_factors``)."""
        from dataclasses import replace

        from .strength import strength_factors

        return replace(self, strength=strength_factors(spec, geometry, flank, self.contact_limit_mpa,
                                                       {m: self.material[m]["type"] for m in self.material}))

    def root_influence(self, member: str) -> float:
        """Y_X Y_RrelT at the member's load cycles (1 without :meth:`with_strength`)."""
        s = self.strength.get(member)
        return 1.0 if s is None else s.root_at(self.life_curves(member).y_nt, self.cycles[member])

    def contact_influence(self, member: str) -> float:
        """Z_L Z_v Z_R at the member's load cycles (1 without :meth:`with_strength`)."""
        s = self.strength.get(member)
        return 1.0 if s is None else s.contact_at(self.life_curves(member).z_nt, self.cycles[member])

    def life_curves(self, member: str):
        return materials.MATERIALS[self.material[member]["type"]]

    def Y_NT(self, member: str) -> float:
        return life_factor(self.life_curves(member).y_nt, self.cycles[member])

    def Z_NT(self, member: str) -> float:
        return life_factor(self.life_curves(member).z_nt, self.cycles[member])

    def root_strength_mpa(self, member: str) -> float:
        """sigma_Flim Y_ST Y_NT Y_X Y_RrelT (Y_deltarelT = 1): what S_F divides by sigma_F."""
        return self.root_limit_mpa[member] * Y_ST * self.Y_NT(member) * self.root_influence(member)

    def contact_strength_mpa(self, member: str) -> float:
        """sigma_Hlim Z_NT Z_L Z_v Z_R (Z_W = Z_X = 1): what S_H divides by sigma_H."""
        return self.contact_limit_mpa[member] * self.Z_NT(member) * self.contact_influence(member)

    def material_json(self, member: str) -> dict:
        out = dict(self.material[member])
        out.update(Z_NT=self.Z_NT(member), Y_NT=self.Y_NT(member), load_cycles=self.cycles[member],
                   Z_L_Z_v_Z_R=self.contact_influence(member), Y_X_Y_RrelT=self.root_influence(member))
        return out

    def notes(self) -> list:
        k_v = {"user": f"K_v = {self.K_v:g} is the user's (rating.K_v)",
               "method B": f"K_v = {self.K_v:.4g} by ISO 6336-1 method B from the pinion speed and the loaded "
                           "contact's mesh stiffness (dynamic_factor)",
               "static": "K_v = 1: no rating.pinion_speed_rpm (static; give the speed for ISO 6336-1 method B)",
               "not computed": "K_v = 1: method B needs a converged LTCA position with a mesh stiffness, and "
                               "none converged (give rating.K_v)"}
        out = [f"{ISO_EDITION} on the virtual helical gear of each section "
               "(docs/rating.md); Y_B = Y_DT = Z_B = Z_D = K_Falpha = K_Halpha = 1",
               f"K_A = {self.K_A:g} is the user's; {k_v[self.K_v_source]}; the local stresses are at K_A K_v T",
               "permissible stresses: sigma_Flim Y_ST Y_NT Y_X Y_RrelT (Y_ST = 2) and sigma_Hlim Z_NT Z_L Z_v Z_R "
               "(ISO 6336-2/-3 method B where their inputs are given, else 1: strength_factors); Y_deltarelT = Z_W "
               "= Z_X = 1"]
        for member in ("pinion", "gear"):
            m = self.material[member]
            out.append(f"{member}: {m['type']} {m['quality']} ({m['iso']}), sigma_Hlim {self.contact_limit_mpa[member]:g} "
                       f"MPa ({m['sigma_Hlim_from']}), sigma_Flim {self.root_limit_mpa[member]:g} MPa "
                       f"({m['sigma_Flim_from']})")
        if self.cycles["pinion"] is None:
            out.append("no rating.pinion_speed_rpm / rating.life_hours: life factors Y_NT = Z_NT = 1 (long life)")
        else:
            out.append(f"load cycles N_L: pinion {self.cycles['pinion']:.3g}, gear {self.cycles['gear']:.3g} "
                       "(life factors of each member's material, ISO 6336-2/-3:2019, no limited pitting)")
        return out

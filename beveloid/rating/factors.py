"""Load factors, life factors and permissible stresses of the rating (docs/rating.md, 4).

What is modelled and what is left at 1 is said here once; ``notes(...)`` repeats it in the output.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from .iso6336 import ISO_EDITION

__all__ = ["Factors", "LIFE_POINTS_CONTACT", "LIFE_POINTS_ROOT", "Y_ST", "face_factor_exponent", "life_factor"]

#: stress correction factor of the reference test gear (ISO 6336-3: sigma_FE = sigma_Flim Y_ST)
Y_ST = 2.0
#: life factor Z_NT of case-hardened steel, ISO 6336-2:2019 Table 2 (no limited pitting): (load cycles, Z_NT),
#: log-log between the points, constant outside
LIFE_POINTS_CONTACT = ((1e5, 1.6), (5e7, 1.0), (1e10, 0.85))
#: life factor Y_NT of case-hardened steel, ISO 6336-3:2019 Table 3: (load cycles, Y_NT)
LIFE_POINTS_ROOT = ((1e3, 2.5), (3e6, 1.0), (1e10, 0.85))


def life_factor(points, cycles: float | None) -> float:
    """The life factor at ``cycles`` load cycles (None: long life, 1)."""
    if cycles is None:
        return 1.0
    if cycles <= points[0][0]:
        return points[0][1]
    for (n0, f0), (n1, f1) in zip(points[:-1], points[1:]):
        if cycles <= n1:
            t = math.log(cycles / n0) / math.log(n1 / n0)
            return math.exp(math.log(f0) + t * (math.log(f1) - math.log(f0)))
    return points[-1][1]


def face_factor_exponent(face_width_mm: float, tooth_depth_mm: float) -> float:
    """N_F of ISO 6336-1:2019 (K_Fbeta = K_Hbeta^N_F), b/h at least 3."""
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

    @classmethod
    def from_spec(cls, spec) -> "Factors":
        r, m = spec.rating, spec.material
        n1 = None
        if r.pinion_speed_rpm is not None and r.life_hours is not None:
            n1 = 60.0 * r.pinion_speed_rpm * r.life_hours
        ratio = spec.pinion.teeth / spec.gear.teeth
        return cls(r.K_A, r.K_v, r.S_Fmin, r.S_Hmin,
                   {"pinion": m.pinion_root_stress_limit_mpa, "gear": m.gear_root_stress_limit_mpa},
                   {"pinion": m.pinion_contact_stress_limit_mpa, "gear": m.gear_contact_stress_limit_mpa},
                   {"pinion": n1, "gear": None if n1 is None else n1 * ratio})

    def Y_NT(self, member: str) -> float:
        return life_factor(LIFE_POINTS_ROOT, self.cycles[member])

    def Z_NT(self, member: str) -> float:
        return life_factor(LIFE_POINTS_CONTACT, self.cycles[member])

    def root_strength_mpa(self, member: str) -> float:
        """sigma_Flim Y_ST Y_NT (Y_deltarelT = Y_RrelT = Y_X = 1): what S_F divides by sigma_F."""
        return self.root_limit_mpa[member] * Y_ST * self.Y_NT(member)

    def contact_strength_mpa(self, member: str) -> float:
        """sigma_Hlim Z_NT (Z_L = Z_v = Z_R = Z_W = Z_X = 1): what S_H divides by sigma_H."""
        return self.contact_limit_mpa[member] * self.Z_NT(member)

    def notes(self) -> list:
        out = [f"{ISO_EDITION} on the virtual helical gear of each section "
               "(docs/rating.md); Y_B = Y_DT = Z_B = Z_D = K_Falpha = K_Halpha = 1",
               f"K_A = {self.K_A:g} and K_v = {self.K_v:g} are the user's; the local stresses are at K_A K_v T",
               "permissible stresses: sigma_Flim Y_ST Y_NT (Y_ST = 2) and sigma_Hlim Z_NT; size, roughness, "
               "lubricant, velocity and work-hardening factors (Y_X, Y_deltarelT, Y_RrelT, Z_X, Z_L, Z_v, Z_R, Z_W) = 1"]
        if self.cycles["pinion"] is None:
            out.append("no rating.pinion_speed_rpm / rating.life_hours: life factors Y_NT = Z_NT = 1 (long life)")
        else:
            out.append(f"load cycles N_L: pinion {self.cycles['pinion']:.3g}, gear {self.cycles['gear']:.3g} "
                       "(life factors of case-hardened steel, ISO 6336-2/-3:2019)")
        return out

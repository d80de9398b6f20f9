"""The dynamic factor K_v by ISO 6336-1 method B (docs/rating.md 4.2), from the pinion speed and the
mesh stiffness of the loaded contact.

Pure functions of plain numbers (no beveloid types), so a hand computation can hold them:

* the deviations of the accuracy grade Q (ISO 1328-1:1995, 5.x: the grade-5 values times
  2^((Q - 5)/2)): f_pt = 0.3 (m_n + 0.4 sqrt(d)) + 4, f_falpha = 2.5 sqrt(m_n) + 0.17 sqrt(d) + 0.5 (um,
  m_n and d in mm), not rounded; f_pb = f_pt cos(alpha_t);
* running-in (ISO 6336-1, 8.3.x): y_alpha = 0.075 f_pb <= 3 um (case-hardened, nitrided,
  nitrocarburised), 160/sigma_Hlim f_pb (through-hardened; <= 12800/sigma_Hlim um for 5 < v <= 10 m/s,
  <= 6400/sigma_Hlim for v > 10), 0.275 f_pb (cast iron; <= 22 um for 5 < v <= 10, <= 11 for v > 10);
  the pair's the mean of its members'; y_p = y_alpha, y_f the same with f_falpha for f_pb;
* the running-in amount C_ay = (sigma_Hlim/97 - 18.45)^2 / 18 + 1.5 um (mean of the members), the
  C_a of a pair without tip relief;
* the resonance (6.5.2, 6.5.9): n_E1 = 30000/(pi z_1) sqrt(c_gamma_alpha / m_red) rpm, N = n_1/n_E1,
  m_red = m_1* m_2* / (m_1* + m_2*), m_i* = pi/8 rho d_mi^4 (1 - q_i^4) / d_bi^2;
* the regions and factors (6.5.3-6.5.8): N_S = 0.5 + 0.35 sqrt(K_A F_t/b / 100) (K_A F_t/b < 100 N/mm),
  else 0.85; B_p = c' f_pb,eff / (K_A F_t/b), B_f = c' f_f,eff / (K_A F_t/b), B_k = |1 - c' C_a/(K_A F_t/b)|;
  sub-critical (N <= N_S) K_v = N (C_v1 B_p + C_v2 B_f + C_v3 B_k) + 1; main resonance (N_S < N <= 1.15)
  K_v = C_v1 B_p + C_v2 B_f + C_v4 B_k + 1; super-critical (N >= 1.5) K_v = C_v5 B_p + C_v6 B_f + C_v7;
  intermediate (1.15 < N < 1.5) linear in N between K_v(1.15) and K_v(1.5); C_v1..C_v7 of Table 8 over
  the total contact ratio eps_gamma.
"""
from __future__ import annotations

import math
import typing
from dataclasses import asdict, dataclass

__all__ = ["DynamicFactor", "MeshDynamics", "accuracy_deviations_um", "c_v", "dynamic_factor", "reduced_mass_kg_per_mm",
           "running_in_um", "tip_relief_running_in_um"]


def accuracy_deviations_um(grade: int, normal_module_mm: float, reference_diameter_mm: float) -> tuple:
    """(f_pt, f_falpha) in um of ISO 1328-1:1995 for accuracy grade ``grade`` (unrounded)."""
    m, d = normal_module_mm, reference_diameter_mm
    step = 2.0 ** ((grade - 5) / 2)
    return (0.3 * (m + 0.4 * math.sqrt(d)) + 4.0) * step, (2.5 * math.sqrt(m) + 0.17 * math.sqrt(d) + 0.5) * step


def running_in_um(group: str, deviation_um: float, sigma_hlim_mpa: float, pitch_velocity_m_s: float) -> float:
    """y_alpha of one member (ISO 6336-1) for a deviation (f_pb, or f_falpha for y_f)."""
    v = pitch_velocity_m_s
    if group == "hardened":
        return min(0.075 * deviation_um, 3.0)
    if group == "through-hardened":
        y = 160.0 / sigma_hlim_mpa * deviation_um
        cap = math.inf if v <= 5 else (12800.0 if v <= 10 else 6400.0) / sigma_hlim_mpa
        return min(y, cap)
    if group == "cast-iron":
        cap = math.inf if v <= 5 else (22.0 if v <= 10 else 11.0)
        return min(0.275 * deviation_um, cap)
    raise ValueError(f"running-in group {group!r}")


def tip_relief_running_in_um(sigma_hlim_mpa: float) -> float:
    """C_ay = (sigma_Hlim/97 - 18.45)^2 / 18 + 1.5 um."""
    return (sigma_hlim_mpa / 97.0 - 18.45) ** 2 / 18.0 + 1.5


def reduced_mass_kg_per_mm(d_m1, d_b1, q1, rho1, d_m2, d_b2, q2, rho2) -> float:
    """m_red = m1* m2* / (m1* + m2*), m_i* = pi/8 rho_i d_mi^4 (1 - q_i^4) / d_bi^2 (kg/mm; mm, kg/mm^3)."""
    m1 = math.pi / 8 * rho1 * d_m1 ** 4 * (1 - q1 ** 4) / d_b1 ** 2
    m2 = math.pi / 8 * rho2 * d_m2 ** 4 * (1 - q2 ** 4) / d_b2 ** 2
    return m1 * m2 / (m1 + m2)


def c_v(eps_gamma: float) -> tuple:
    """(C_v1, ..., C_v7) of ISO 6336-1 Table 8 (the 1 < eps_gamma <= 2 values also below 1)."""
    e = eps_gamma
    if e <= 2.0:
        c2, c3, c4, c6 = 0.34, 0.23, 0.90, 0.47
    else:
        c2, c3, c4, c6 = 0.57 / (e - 0.3), 0.096 / (e - 1.56), (0.57 - 0.05 * e) / (e - 1.44), 0.12 / (e - 1.74)
    c7 = 0.75 if e <= 1.5 else (0.125 * math.sin(math.pi * (e - 2.0)) + 0.875 if e <= 2.5 else 1.0)
    return 0.32, c2, c3, c4, 0.47, c6, c7


@dataclass(frozen=True)
class DynamicFactor:
    """K_v by method B and what it came from (the JSON's ``dynamic_factor``)."""

    K_v: float
    region: str  # "sub-critical", "main resonance", "intermediate", "super-critical"
    resonance_ratio: float  # N
    resonance_speed_rpm: float  # n_E1
    N_S: float
    c_gamma_alpha_n_per_mm_um: float
    c_prime_n_per_mm_um: float
    m_red_kg_per_mm: float
    line_load_n_per_mm: float  # K_A F_t / b
    f_pb_eff_um: float
    f_f_eff_um: float
    C_a_um: float
    B_p: float
    B_f: float
    B_k: float
    eps_gamma: float
    C_v: tuple

    def as_dict(self) -> dict:
        return asdict(self)


class MeshDynamics(typing.NamedTuple):
    """What method B reads of the pair (stiffness in N/(mm um), m_red kg/mm, line load K_A F_t/b)."""

    pinion_speed_rpm: float
    pinion_teeth: int
    c_gamma_alpha: float  # mesh stiffness per face width, N/(mm um)
    c_prime: float  # single pair stiffness, N/(mm um)
    m_red: float  # reduced mass per face width, kg/mm
    line_load_n_per_mm: float  # K_A F_t / b
    f_pb_eff_um: float  # effective base pitch deviation (after running-in)
    f_f_eff_um: float  # effective profile form deviation (after running-in)
    C_a_um: float  # tip relief
    eps_gamma: float  # total contact ratio


def dynamic_factor(mesh: MeshDynamics) -> DynamicFactor:
    """ISO 6336-1 method B (module docstring) of the pair ``mesh``."""
    (pinion_speed_rpm, pinion_teeth, c_gamma_alpha, c_prime, m_red, line_load_n_per_mm, f_pb_eff_um, f_f_eff_um, C_a_um,
     eps_gamma) = mesh
    n_e1 = 30000.0 / (math.pi * pinion_teeth) * math.sqrt(c_gamma_alpha / m_red)
    N = pinion_speed_rpm / n_e1
    w = line_load_n_per_mm
    n_s = 0.5 + 0.35 * math.sqrt(w / 100.0) if w < 100.0 else 0.85
    fpb, ff = max(f_pb_eff_um, 0.0), max(f_f_eff_um, 0.0)
    bp, bf, bk = c_prime * fpb / w, c_prime * ff / w, abs(1.0 - c_prime * C_a_um / w)
    cv = c_v(eps_gamma)
    resonance = cv[0] * bp + cv[1] * bf + cv[3] * bk + 1.0
    supercritical = cv[4] * bp + cv[5] * bf + cv[6]
    if N <= n_s:
        kv, region = N * (cv[0] * bp + cv[1] * bf + cv[2] * bk) + 1.0, "sub-critical"
    elif N <= 1.15:
        kv, region = resonance, "main resonance"
    elif N < 1.5:
        kv, region = supercritical + (resonance - supercritical) * (1.5 - N) / 0.35, "intermediate"
    else:
        kv, region = supercritical, "super-critical"
    return DynamicFactor(kv, region, N, n_e1, n_s, c_gamma_alpha, c_prime, m_red, w, fpb, ff, C_a_um, bp, bf, bk,
                         eps_gamma, cv)

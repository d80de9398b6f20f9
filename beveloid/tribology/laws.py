"""The formulas of the tribology, each from its source (docs/tribology.md lists them).

Units as named; every function broadcasts over numpy arrays.
"""
from __future__ import annotations

import math

import numpy as np

#: ISO/TR 14179-2 (Schlenk): mu = SCHLENK (F_bt/b / (v_sum rho_red))^0.2 eta^-0.05 Ra^0.25 X_L
SCHLENK = 0.048
#: Blok's flash temperature of a semi-elliptic (Hertzian) band source at high Peclet number
BLOK = 1.11
#: steel's heat conduction (W/(m K)), density (kg/m^3) and specific heat (J/(kg K)): B_M = sqrt(l rho c)
STEEL_CONDUCTIVITY = 45.0
STEEL_DENSITY = 7800.0
STEEL_SPECIFIC_HEAT = 420.0
#: ISO/TS 6336-20: the bulk temperature theta_M = theta_oil + BULK * X_S * X_mp * theta_fl,max
BULK = 0.47
SPRAY_FACTOR_XS = 1.0  #: X_S: 1.0 dip lubrication (1.2 spray)
MESH_FACTOR_XMP = 1.0  #: X_mp: one mating gear
STRUCTURAL_FACTOR_XW = 1.0  #: X_W of the scuffing temperature (case-hardened, usual retained austenite)


def thermal_contact_coefficient():
    """B_M = sqrt(lambda rho c) of steel (N/(m s^0.5 K))."""
    return math.sqrt(STEEL_CONDUCTIVITY * STEEL_DENSITY * STEEL_SPECIFIC_HEAT)


def schlenk_mu(line_load_n_per_mm, sum_velocity_m_s, reduced_radius_mm, eta_mpa_s, ra_um, xl):
    """ISO/TR 14179-2's mean coefficient of friction (Schlenk) for a line load (N/mm), sum velocity
    (m/s), reduced radius of curvature in its direction (mm), the oil's dynamic viscosity (mPa s) at its
    temperature, the mean roughness Ra = (Ra1 + Ra2)/2 (um) and the lubricant factor X_L."""
    with np.errstate(divide="ignore", invalid="ignore"):
        x = np.asarray(line_load_n_per_mm, dtype=float) / (np.asarray(sum_velocity_m_s) * reduced_radius_mm)
        return SCHLENK * np.power(x, 0.2) * eta_mpa_s ** -0.05 * ra_um ** 0.25 * xl


def hamrock_dowson(entraining_m_s, rx_mm, ry_mm, load_n, eta_pa_s, alpha_1_per_pa, e_prime_pa):
    """Hamrock & Dowson (1977) central and minimum film thickness (um) of an elliptical EHL contact:
    entraining speed u (m/s) along x, reduced radii R_x (along u) and R_y (mm), normal load w (N).

        H_c   = 2.69 U^0.67 G^0.53 W^-0.067 (1 - 0.61 exp(-0.73 k))
        H_min = 3.63 U^0.68 G^0.49 W^-0.073 (1 - exp(-0.68 k)),   k = 1.0339 (R_y/R_x)^0.636

    with U = eta u / (E' R_x), G = alpha E', W = w / (E' R_x^2), H = h / R_x."""
    rx = np.asarray(rx_mm, dtype=float) * 1e-3
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        ratio = np.asarray(ry_mm, dtype=float) / np.asarray(rx_mm, dtype=float)
        k = 1.0339 * np.power(ratio, 0.636)
        u = eta_pa_s * np.asarray(entraining_m_s) / (e_prime_pa * rx)
        g = alpha_1_per_pa * e_prime_pa
        w = np.asarray(load_n) / (e_prime_pa * rx * rx)
        hc = 2.69 * u ** 0.67 * g ** 0.53 * w ** -0.067 * (1 - 0.61 * np.exp(-0.73 * k))
        hm = 3.63 * u ** 0.68 * g ** 0.49 * w ** -0.073 * (1 - np.exp(-0.68 * k))
    return hc * rx * 1e6, hm * rx * 1e6


def line_contact_film(entraining_m_s, rx_mm, line_load_n_per_mm, eta_pa_s, alpha_1_per_pa, e_prime_pa):
    """Central and minimum film thickness (um) of an EHL line contact, load w' (N/mm) per unit length:

        H_c   = 3.06 U^0.69 G^0.56 W'^-0.10     (Dowson & Toyoda 1979)
        H_min = 2.65 U^0.70 G^0.54 W'^-0.13     (Dowson & Higginson 1977; ISO/TS 6336-22's film is of its form)

    with U = eta u / (E' R_x), G = alpha E', W' = w' / (E' R_x), H = h / R_x."""
    rx = np.asarray(rx_mm, dtype=float) * 1e-3
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        u = eta_pa_s * np.asarray(entraining_m_s) / (e_prime_pa * rx)
        g = alpha_1_per_pa * e_prime_pa
        w = np.asarray(line_load_n_per_mm) * 1e3 / (e_prime_pa * rx)
        hc = 3.06 * u ** 0.69 * g ** 0.56 * w ** -0.10
        hm = 2.65 * u ** 0.70 * g ** 0.54 * w ** -0.13
    return hc * rx * 1e6, hm * rx * 1e6


def hertz_half_width_mm(line_load_n_per_mm, radius_mm, e_prime_mpa):
    """Half width b of a Hertz line contact (mm): b = sqrt(8 w' R / (pi E'))."""
    with np.errstate(invalid="ignore"):
        return np.sqrt(8.0 * np.asarray(line_load_n_per_mm) * radius_mm / (math.pi * e_prime_mpa))


def blok_flash_c(mu, line_load_n_per_mm, sliding_m_s, v1_m_s, v2_m_s, half_width_mm, b1=None, b2=None):
    """Blok's flash temperature (K above the bulk) of a band heat source: 1.11 mu w' |v_s| /
    ((B_1 sqrt(v_1) + B_2 sqrt(v_2)) sqrt(b)), w' (N/m), b (m), surface speeds v_i relative to the
    contact (m/s), B_i = sqrt(lambda rho c) (N/(m s^0.5 K)); steel's by default."""
    b1 = thermal_contact_coefficient() if b1 is None else b1
    b2 = thermal_contact_coefficient() if b2 is None else b2
    with np.errstate(divide="ignore", invalid="ignore"):
        return (BLOK * np.asarray(mu) * np.asarray(line_load_n_per_mm) * 1e3 * np.abs(sliding_m_s)
                / ((b1 * np.sqrt(v1_m_s) + b2 * np.sqrt(v2_m_s)) * np.sqrt(np.asarray(half_width_mm) * 1e-3)))


def bulk_temperature_c(oil_c, flash_max_c):
    """ISO/TS 6336-20's bulk temperature theta_M = theta_oil + 0.47 X_S X_mp theta_fl,max."""
    return oil_c + BULK * SPRAY_FACTOR_XS * MESH_FACTOR_XMP * flash_max_c


def scuffing_temperature_c(fzg_load_stage, xl):
    """ISO/TS 6336-20's scuffing temperature from the FZG load stage:
    theta_S = 80 + (0.85 + 1.4 X_W) X_L S_FZG^2 (C)."""
    return 80.0 + (0.85 + 1.4 * STRUCTURAL_FACTOR_XW) * xl * fzg_load_stage ** 2


def scuffing_safety(scuffing_c, contact_max_c, oil_c):
    """ISO/TS 6336-20's flash-temperature safety S_B = (theta_S - theta_oil) / (theta_B,max - theta_oil)."""
    return (scuffing_c - oil_c) / (contact_max_c - oil_c)


def ohlendorf_hv(z1, u, eps1, eps2, cos_beta_b=1.0):
    """ISO/TR 14179-2's (Ohlendorf) tooth loss factor H_V = pi (u + 1)/(z1 u cos beta_b)
    (1 - eps_a + eps_1^2 + eps_2^2), eps_a = eps_1 + eps_2 (the addendum contact ratios)."""
    ea = eps1 + eps2
    return math.pi * (u + 1) / (z1 * u * cos_beta_b) * (1 - ea + eps1 ** 2 + eps2 ** 2)

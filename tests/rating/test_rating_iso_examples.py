"""ISO 6336-2/-3 against published worked examples, to the printed digits.

Every value is asserted to half a unit of its last printed digit (kst-B: see below).  The sources are public
transcriptions of printed reports; where two independent ones overlap they agree.

1. Spur: the FZG-C test gear pair, rated by STplus 11.1F (FVA / FZG TU Muenchen, release
   01.12.2025; the commercial reference implementation of the FVA) with "ISO 6336 Teil 1-3 (2019)",
   method B.  Its full listing is public in the repository tkuhn39/semesterthesis,
   20_code/10_gearcore/src/gearcore/data/stplus/fzg_c/report.sta.txt (sheets 5-12: echo of the
   input, "Geometrieberechnung nach DIN 3960", "Daten am kritischen Zahnfussquerschnitt",
   "ISO 6336 Teil 1-3 (2019)").  Inputs: z = 16/24, m_n = 4.5 mm, alpha_n = 20 deg, beta = 0,
   a = 91.5 mm, x1 = 0.1818 (x2 from a), d_a = 82.45/118.35 mm, b = 14 mm, hob h_aP0* = 1.39
   (= h_fP*), rho_aP0* = 0.25, no protuberance, upper tooth thickness allowance A_sne = -0.085 mm
   (both), T_1 = 130 N m, E = 210 000 N/mm^2, nu = 0.3.
   Spur, second listing: "kst-B" (STplus 9.0F, "ISO 6336 Teil 1-3 (1996)"; its method B, Z_H,
   Z_E and Z_eps are reproduced by our 2019 implementation), same repository,
   .../stplus/kst_b/report.sta.txt (sheets 2-13): z = 36/54, m_n = 2 mm, a = 91.5 mm, x1 = 0.2407, d_a = 76.46/112.95 mm with the
   wheel's tip chamfered by its hob to the tip form circle d_Fa = 112.376 mm, b = 22/20 mm, hobs
   h_aP0* = 1.25, rho_aP0* = 0.25/0.394, x_E = 0.1823/0.3037 (from the measured spans), P = 400 kW
   at 1000 1/min (T_1 = 3819.72 N m).  x_E is printed to 4 decimals and STplus iterates it to its
   geometry tolerance DESTGR = 0.0002 (printed on sheet 5): sigma_F0 moves by 0.2 N/mm^2 within that
   rounding, so this listing is held with ours evaluated at x_E -+ 0.00005.
2. Helical: ISO/TR 6336-30:2017, Annex A, example 1 ("single helical case carburized gear pair"),
   the pitting results.  Inputs (Table A.1): z = 17/103, m_n = 8 mm, alpha_n = 20 deg,
   beta = 15.8 deg, b = 100 mm, a_w = 500 mm, x2 = 0 (x1 = (0.14522) printed in parentheses: it
   follows from a_w), d_a = 159.66/872.35 mm, h_fP = 1.4 m_n, rho_fP = 0.39 m_n, transcribed in the
   test data of the same repository (gearcore worked example "ISO/TR 6336-30:2022 Annex A
   example 1", its decimal reference cases "A"/"H").  Load and results: T_1 = 9000 N m; printed
   F_t = 127 352 N, z_n = 18.905/114.543, Z_H = 2.39533, Z_E = 189.81170 (steel, E = 206 000 N/mm^2,
   nu = 0.3), Z_eps = 0.803, Z_beta = 1.01944, sigma_H0 = 1206.58207 N/mm^2, transcribed as the
   reference column of ``MATISO_6336.example_01`` in the open-source MATLAB project
   gfsReboucas/Drivetrain ("compares the results against the values found in
   [ISO/TR 6336-30:2017], Annex A").  sigma_H0 holds to the printed digits only with the unrounded
   F_t = 2 T_1 / d_1 (with the printed 127 352 N it is 1206.5797): the TR carries F_t unrounded,
   as this test does.

What the spur example settles: STplus generates the root (s_Fn, rho_F, and the tooth's half angle
gamma_e at d_en, hence alpha_Fen and h_Fe) at the generating profile shift x_E = x + A_sne /
(2 m_n tan alpha_n) of the thinned tooth, and the mesh (a, eps_alpha, d_en) at the nominal x; with
x in place of x_E, the pinion's Y_F is 2.009 instead of 2.087
(``CylindricalGear.generating_profile_shift``; held by a test below).

3. Helical bending: a KISSsoft 03/2017 report to ISO 6336:2006 method B (beta = 10 deg, eps_beta = 1.42),
   public in gfsReboucas/Drivetrain, @NREL_5MW/stage_03.rtf (section 3 below).  It prints the 2006
   Y_beta; the 2019 pair (Y_beta over cos^3 beta, f_eps in Y_F) has no public printed helical
   example (docs/rating.md 3.1), so the 2019 Y_beta is held to the standard's Figure 8
   (test_rating_iso6336.py).  alpha_Fen, h_F, the pinion's Y_S and sigma_F0 of that report are held
   to a stated band, not to the printed digits (under 0.1 % in sigma_F0; the cause is open).
4. The permissible stresses' factors of the FZG-C listing (section 4 below): Z_L, Z_v, Z_R (its R_z10), their
   product, Y_X and Y_RrelT of STplus 11.1F (ISO 6336:2019), from the listing's oil, flank Ra, root R_z
   and pitch-line velocity (beveloid/rating/strength.py, docs/rating.md 4.4).
"""
from __future__ import annotations

import dataclasses
import math

import pytest

from beveloid.rating import iso6336 as iso


def _within_printed(ours, printed, decimals):
    """|ours - printed| <= half a unit of the last printed digit."""
    return abs(ours - printed) <= 0.5 * 10.0 ** -decimals * (1 + 1e-9)


def _shift_sum(z1, z2, m_n, alpha_n, beta, a_w):
    """x1 + x2 at centre distance a_w, zero backlash: inv a_wt = inv a_t + 2 tan a_n (x1 + x2)/(z1 + z2)."""
    alpha_t = math.atan(math.tan(alpha_n) / math.cos(beta))
    a0 = (z1 + z2) * m_n / math.cos(beta) / 2
    alpha_wt = math.acos(a0 * math.cos(alpha_t) / a_w)
    return (iso.inv(alpha_wt) - iso.inv(alpha_t)) * (z1 + z2) / (2 * math.tan(alpha_n))


def _bending(pair, m_n, ft_n, b_mm):
    bg = iso.bending_geometry(pair)
    y_beta = iso.helix_factor_bending(pair.overlap_ratio, pair.gear.helix_angle)
    return {
        "alpha_Fen_deg": math.degrees(bg.alpha_Fen),
        "s_Fn_star": bg.s_Fn_mm / m_n,
        "h_Fe_star": bg.h_Fe_mm / m_n,
        "rho_F_star": bg.rho_F_mm / m_n,
        "q_s": bg.s_Fn_mm / (2 * bg.rho_F_mm),
        "Y_F": bg.Y_F,
        "Y_S": bg.Y_S,
        "Y_beta": y_beta,
        "sigma_F0_mpa": iso.nominal_root_stress_mpa(ft_n, b_mm, m_n, bg.Y_F, bg.Y_S, y_beta),
    }


# --- 1. spur: STplus listings (FZG-C: STplus 11.1F, ISO 6336:2019; kst-B: STplus 9.0F, ISO 6336:1996)

FZG_C = {"z": (16, 24), "m_n": 4.5, "a": 91.5, "x1": 0.1818, "d_a": (82.45, 118.35), "b": (14.0, 14.0),
         "h_fP": (1.39, 1.39), "rho_fP": (0.25, 0.25), "A_sne": (-0.085, -0.085), "T1_nm": 130.0}
# kst-B: x_E is given by the listing (STplus derives it from the measured spans), the wheel's tip is
# chamfered by its hob (h_K = 0.287 mm): its mesh ends at the tip form circle d_Fa = 112.376 mm
KST_B = {"z": (36, 54), "m_n": 2.0, "a": 91.5, "x1": 0.2407, "d_a": (76.46, 112.376), "b": (22.0, 20.0),
         "h_fP": (1.25, 1.25), "rho_fP": (0.25, 0.394), "x_E": (0.1823, 0.3037), "T1_nm": 3819.72}


def _stplus_gears(case, x_e=None, allowance=True):
    m_n, alpha_n = case["m_n"], math.radians(20.0)
    x = (case["x1"], _shift_sum(*case["z"], m_n, alpha_n, 0.0, case["a"]) - case["x1"])
    if x_e is None and "A_sne" in case:
        x_e = [xi + a / (2 * m_n * math.tan(alpha_n)) for xi, a in zip(x, case["A_sne"])]
    x_e = x_e if x_e is not None else case["x_E"]
    return [iso.CylindricalGear(case["z"][i], m_n, alpha_n, 0.0, x[i], case["d_a"][i], case["h_fP"][i] * m_n,
                                case["rho_fP"][i] * m_n, x_e[i] if allowance else None) for i in (0, 1)]


def _stplus_values(case, x_e=None):
    pinion, wheel = _stplus_gears(case, x_e)
    b_common = min(case["b"])
    pair = iso.CylindricalPair(pinion, wheel, b_common)
    f = iso.contact_factors(pair, 210000.0, 0.3, 210000.0, 0.3)
    d1 = pinion.reference_diameter_mm
    ft = 2 * case["T1_nm"] * 1e3 / d1
    common = {
        "a_mm": pair.center_distance_mm, "eps_alpha": pair.transverse_contact_ratio, "F_t_n": ft,
        "Z_H": f.Z_H, "Z_E": f.Z_E, "Z_eps": f.Z_eps, "Z_beta": f.Z_beta,
        "sigma_H0_mpa": iso.nominal_contact_stress_mpa(f, ft, d1, b_common, case["z"][1] / case["z"][0]),
    }
    members = {}
    for i, (name, g, mate) in enumerate((("pinion", pinion, wheel), ("wheel", wheel, pinion))):
        members[name] = {"x_E": g.root_profile_shift, "z_n": iso.virtual_teeth(g),
                         **_bending(iso.CylindricalPair(g, mate, b_common), case["m_n"], ft, case["b"][i])}
    return {"common": common, **members}


def _printed(pair_rows, member_rows):
    """(where, quantity, value, decimals) from (quantity, value, decimals) of the pair and
    (quantity, (pinion, wheel), decimals) of the members."""
    return [("common", n, v, d) for n, v, d in pair_rows] + [
        (member, n, v[i], d) for n, v, d in member_rows for i, member in enumerate(("pinion", "wheel"))]


# FZG-C, sheets 5 (geometry), 7 (x_E), 9-12 (rating)
FZG_C_PRINTED = _printed(
    [("a_mm", 91.5, 3), ("eps_alpha", 1.436, 3), ("F_t_n", 3611.1, 1), ("Z_H", 2.342, 3), ("Z_E", 191.6, 1),
     ("Z_eps", 0.924, 3), ("Z_beta", 1.000, 3), ("sigma_H0_mpa", 1013.8, 1)],
    [("x_E", (0.1559, 0.1454), 4), ("z_n", (16.000, 24.000), 3), ("alpha_Fen_deg", (23.206, 22.975), 3),
     ("s_Fn_star", (1.933, 2.089), 3), ("h_Fe_star", (1.329, 1.385), 3), ("rho_F_star", (0.501, 0.479), 3),
     ("q_s", (1.93, 2.18), 2), ("Y_F", (2.087, 1.866), 3), ("Y_S", (1.758, 1.856), 3),
     ("Y_beta", (1.000, 1.000), 3), ("sigma_F0_mpa", (210.3, 198.5), 1)])
# kst-B, sheets 6 (geometry), 10-13 (rating, "ISO 6336 Teil 1-3 (1996)")
KST_B_PRINTED = _printed(
    [("a_mm", 91.5, 3), ("eps_alpha", 1.188, 3), ("F_t_n", 106103.3, 1), ("Z_H", 2.342, 3), ("Z_E", 191.6, 1),
     ("Z_eps", 0.968, 3), ("Z_beta", 1.000, 3), ("sigma_H0_mpa", 4815.7, 1)],
    [("z_n", (36.000, 54.000), 3), ("alpha_Fen_deg", (24.721, 23.239), 3), ("s_Fn_star", (2.179, 2.256), 3),
     ("h_Fe_star", (1.581, 1.390), 3), ("rho_F_star", (0.393, 0.451), 3), ("q_s", (2.77, 2.50), 2),
     ("Y_F", (1.932, 1.603), 3), ("Y_S", (1.964, 2.000), 3), ("Y_beta", (1.000, 1.000), 3),
     ("sigma_F0_mpa", (9151.8, 8504.1), 1)])


@pytest.fixture(scope="module")
def fzg_c():
    return _stplus_values(FZG_C)


@pytest.fixture(scope="module")
def kst_b_range():
    """kst-B's x_E is an input printed to 4 decimals: our values at x_E -+ 0.00005 bound what that
    printed input allows (each member's root depends on its own x_E only)."""
    lo, hi = ([x + d for x in KST_B["x_E"]] for d in (-0.5e-4, 0.5e-4))
    return _stplus_values(KST_B, lo), _stplus_values(KST_B, hi)


@pytest.mark.parametrize("where, name, printed, decimals", FZG_C_PRINTED,
                         ids=[f"{w}-{n}" for w, n, _, _ in FZG_C_PRINTED])
def test_stplus_fzg_c_spur_iso_6336_2019(fzg_c, where, name, printed, decimals):
    """FZG-C (spur) rated by STplus 11.1F to ISO 6336-2/-3:2019 method B: ours rounds to the printed value."""
    ours = fzg_c[where][name]
    assert _within_printed(ours, printed, decimals), f"{where} {name}: ours {ours!r}, printed {printed}"


@pytest.mark.parametrize("where, name, printed, decimals", KST_B_PRINTED,
                         ids=[f"{w}-{n}" for w, n, _, _ in KST_B_PRINTED])
def test_stplus_kst_b_spur_iso_6336_1996(kst_b_range, where, name, printed, decimals):
    """kst-B (spur, chamfered wheel tip) rated by STplus 9.0F to ISO 6336:1996 method B: the printed value lies within half a unit of its last digit
    of ours, for an x_E within the printed x_E's own rounding."""
    a, b = (v[where][name] for v in kst_b_range)
    half = 0.5 * 10.0 ** -decimals * (1 + 1e-9)
    assert min(a, b) - half <= printed <= max(a, b) + half, f"{where} {name}: ours {a!r}..{b!r}, printed {printed}"


def test_fzg_c_root_needs_the_generating_profile_shift():
    """Without the tooth thickness allowance (root at the nominal x) the printed Y_F is missed by 4 %:
    the printed root is that of the thinned tooth (x_E), the printed mesh that of the nominal one."""
    pinion, wheel = _stplus_gears(FZG_C, allowance=False)
    bg = iso.bending_geometry(iso.CylindricalPair(pinion, wheel, 14.0))
    assert bg.Y_F == pytest.approx(2.009, abs=5e-4) and not _within_printed(bg.Y_F, 2.087, 3)


# --- 2. helical: ISO/TR 6336-30:2017 Annex A example 1, pitting ---------------------------------

M_N, ALPHA_N, BETA = 8.0, math.radians(20.0), math.radians(15.8)
Z1, Z2, A_W, B = 17, 103, 500.0, 100.0
D_A1, D_A2 = 159.66, 872.35
T1_NMM = 9000.0e3
E_MPA, NU = 206000.0, 0.3


def _gear(z, x, tip_mm):
    return iso.CylindricalGear(z, M_N, ALPHA_N, BETA, x, tip_mm, 1.4 * M_N, 0.39 * M_N)


def _example_1_pair():
    x1 = _shift_sum(Z1, Z2, M_N, ALPHA_N, BETA, A_W)  # x2 = 0
    return iso.CylindricalPair(_gear(Z1, x1, D_A1), _gear(Z2, 0.0, D_A2), B)


@pytest.fixture(scope="module")
def example_1():
    pair = _example_1_pair()
    f = iso.contact_factors(pair, E_MPA, NU, E_MPA, NU)
    d1 = pair.gear.reference_diameter_mm
    ft = 2 * T1_NMM / d1
    return {
        "x1": pair.gear.profile_shift,
        "a_w_mm": pair.center_distance_mm,
        "F_t_n": ft,
        "z_n1": iso.virtual_teeth(pair.gear),
        "z_n2": iso.virtual_teeth(pair.mate),
        "Z_H": f.Z_H,
        "Z_E": f.Z_E,
        "Z_eps": f.Z_eps,
        "Z_beta": f.Z_beta,
        "sigma_H0_mpa": iso.nominal_contact_stress_mpa(f, ft, d1, B, Z2 / Z1),
    }


# (quantity, printed value, printed decimals)
TR_EXAMPLE_1_PRINTED = [
    ("x1", 0.14522, 5),  # Table A.1, in parentheses (derived from a_w)
    ("a_w_mm", 500.0, 2),  # Table A.1 (given)
    ("F_t_n", 127352.0, 0),
    ("z_n1", 18.905, 3),
    ("z_n2", 114.543, 3),
    ("Z_H", 2.39533, 5),
    ("Z_E", 189.81170, 5),
    ("Z_eps", 0.803, 3),
    ("Z_beta", 1.01944, 5),
    ("sigma_H0_mpa", 1206.58207, 5),
]


@pytest.mark.parametrize("name, printed, decimals", TR_EXAMPLE_1_PRINTED, ids=[p[0] for p in TR_EXAMPLE_1_PRINTED])
def test_iso_tr_6336_30_example_1_helical_pitting(example_1, name, printed, decimals):
    """ISO/TR 6336-30:2017 Annex A example 1 (helical, beta = 15.8 deg): ours rounds to the printed value."""
    ours = example_1[name]
    assert _within_printed(ours, printed, decimals), f"{name}: ours {ours!r}, printed {printed}"


def test_example_1_is_in_the_overlap_regime_it_prints():
    """The TR uses Z_eps = sqrt(1/eps_alpha) (eps_beta >= 1); our pair is there too, and the printed
    Z_eps = 0.803 then pins eps_alpha between 1/0.8035^2 and 1/0.8025^2 (1.549 to 1.553)."""
    pair = _example_1_pair()
    assert pair.overlap_ratio >= 1.0
    assert 1 / 0.8035 ** 2 <= pair.transverse_contact_ratio <= 1 / 0.8025 ** 2


def test_iso_tr_6336_30_example_1_tooth_stiffness():
    """ISO 6336-1 method B stiffnesses of example 1 to the printed digits, as the reference column of
    ``MATISO_6336.example_01`` transcribes them: c'_th = 17.8558, c' = 12.3705, c_gamma_alpha = 17.4648
    N/(mm um) (h_fP = 1.4 m_n: C_B = 0.9).  The stiffness lines are those of x1 rounded to the printed
    0.145 (with x1 = 0.14522, c'_th = 17.8566); eps_alpha is the mesh's (from a_w), as in the pitting lines."""
    pair = _example_1_pair()
    printed_x1 = dataclasses.replace(pair, gear=dataclasses.replace(pair.gear, profile_shift=0.145))
    c_prime = iso.single_stiffness_n_per_mm_um(printed_x1)
    assert _within_printed(iso.theoretical_single_stiffness_n_per_mm_um(printed_x1), 17.8558, 4)
    assert _within_printed(c_prime, 12.3705, 4)
    assert _within_printed(c_prime * iso.mesh_to_single_stiffness(pair.transverse_contact_ratio), 17.4648, 4)
    # the mesh stiffness of one pair is its c' times the same factor of its own eps_alpha
    assert iso.mesh_stiffness_n_per_mm_um(pair) == pytest.approx(
        iso.single_stiffness_n_per_mm_um(pair) * (0.75 * pair.transverse_contact_ratio + 0.25), rel=1e-15)


# --- 3. helical bending: KISSsoft 03/2017, ISO 6336:2006 method B (NREL 5 MW gearbox, stage 3) --------
#
# Source: the KISSsoft report "CALCULATION OF A HELICAL GEAR PAIR" (KISSsoft Release 03/2017 A,
# "Calculation method ISO 6336:2006 Method B"), public in the repository gfsReboucas/Drivetrain,
# file @NREL_5MW/stage_03.rtf, sections 1 (geometry), 2 (F_t) and 3 (tooth root strength).  Inputs:
# z = 24/95, m_n = 14 mm, alpha_n = 20 deg, beta = 10 deg, a = 861 mm, x = 0.4800/0.6691,
# d_a = 380.747/1395.376 mm, b = 360/360 mm, basic rack h_fP* = 1.25, rho_fP* = 0.38 (ISO 53 profile
# A, no protuberance), F_t = 240 064.4 N (printed).  The report says the root was "Calculated with
# profile shift [x] 0.4800 0.6691", i.e. at the nominal x.  Y_beta is the 2006 form (printed 0.917
# = 1 - 1 x 10/120 with eps_beta = 1.421 capped at 1).

KISS = {"z": (24, 95), "x": (0.4800, 0.6691), "d_a": (380.747, 1395.376), "m_n": 14.0, "beta_deg": 10.0,
        "b": 360.0, "F_t_n": 240064.4}


def _kiss_values():
    m_n, alpha_n, beta = KISS["m_n"], math.radians(20.0), math.radians(KISS["beta_deg"])
    gears = [iso.CylindricalGear(KISS["z"][i], m_n, alpha_n, beta, KISS["x"][i], KISS["d_a"][i], 1.25 * m_n,
                                 0.38 * m_n) for i in (0, 1)]
    pair = iso.CylindricalPair(gears[0], gears[1], KISS["b"])
    out = {"common": {"a_mm": pair.center_distance_mm, "alpha_wt_deg": math.degrees(pair.working_pressure_angle),
                      "eps_alpha": pair.transverse_contact_ratio, "eps_beta": pair.overlap_ratio}}
    for i, name in enumerate(("pinion", "wheel")):
        member = iso.CylindricalPair(gears[i], gears[1 - i], KISS["b"])
        bg = iso.bending_geometry(member, "2006")
        y_beta = iso.helix_factor_bending(member.overlap_ratio, beta, "2006")
        out[name] = {"z_n": bg.virtual_teeth, "d_en_mm": bg.d_en_mm, "s_Fn_mm": bg.s_Fn_mm,
                     "s_Fn_star": bg.s_Fn_mm / m_n, "rho_F_mm": bg.rho_F_mm, "rho_F_star": bg.rho_F_mm / m_n,
                     "q_s": bg.s_Fn_mm / (2 * bg.rho_F_mm), "alpha_Fen_deg": math.degrees(bg.alpha_Fen),
                     "h_Fe_mm": bg.h_Fe_mm, "Y_F": bg.Y_F, "Y_S": bg.Y_S, "Y_beta": y_beta,
                     "sigma_F0_mpa": iso.nominal_root_stress_mpa(KISS["F_t_n"], KISS["b"], m_n, bg.Y_F, bg.Y_S,
                                                                 y_beta)}
    return out


# to the printed digits (the report's "den" is d_en of the virtual spur gear)
KISS_PRINTED = _printed(
    [("a_mm", 861.000, 3), ("alpha_wt_deg", 22.856, 3), ("eps_alpha", 1.463, 3), ("eps_beta", 1.421, 3)],
    [("z_n", (25.037, 99.104), 3), ("d_en_mm", (369.487, 1415.619), 3), ("s_Fn_mm", (31.18, 32.75), 2),
     ("s_Fn_star", (2.227, 2.340), 3), ("rho_F_star", (0.425, 0.385), 3), ("q_s", (2.620, 3.036), 3),
     ("Y_F", (1.18, 1.24), 2), ("Y_beta", (0.917, 0.917), 3)]) + [("pinion", "rho_F_mm", 5.95, 2),
                                                                  ("wheel", "rho_F_mm", 5.39, 2),
                                                                  ("wheel", "Y_S", 2.35, 2)]
# not to the printed digits: (where, quantity, printed, relative band); measured gaps in the docstring below
KISS_CLOSE = [("pinion", "alpha_Fen_deg", 23.89, 1e-3), ("wheel", "alpha_Fen_deg", 22.20, 1e-3),
              ("pinion", "h_Fe_mm", 14.06, 3e-3), ("wheel", "h_Fe_mm", 16.11, 3e-3), ("pinion", "Y_S", 2.28, 3e-3),
              ("pinion", "sigma_F0_mpa", 117.92, 1.5e-3), ("wheel", "sigma_F0_mpa", 127.69, 1.5e-3)]


@pytest.fixture(scope="module")
def kiss():
    return _kiss_values()


@pytest.mark.parametrize("where, name, printed, decimals", KISS_PRINTED,
                         ids=[f"{w}-{n}" for w, n, _, _ in KISS_PRINTED])
def test_kisssoft_helical_bending_iso_6336_2006(kiss, where, name, printed, decimals):
    """A helical pair (beta = 10 deg, eps_beta = 1.42) rated by KISSsoft 03/2017 to ISO 6336-3:2006 method B:
    the virtual gear, the outer point of single contact, the 30 deg root chord, Y_F and Y_beta round to
    the printed values."""
    ours = kiss[where][name]
    assert _within_printed(ours, printed, decimals), f"{where} {name}: ours {ours!r}, printed {printed}"


@pytest.mark.parametrize("where, name, printed, rel", KISS_CLOSE, ids=[f"{w}-{n}" for w, n, _, _ in KISS_CLOSE])
def test_kisssoft_helical_bending_load_arm_within_a_stated_band(kiss, where, name, printed, rel):
    """Where ours does not round to the printed digits, it is within the stated band: the printed
    alpha_Fen is 0.013 / 0.009 deg larger and h_F 0.19 / 0.14 % longer than ISO's closed form at the
    nominal x and the printed d_en (which ours reproduces to 1e-3 mm), so Y_S (via L = s_Fn/h_F) and
    sigma_F0 (117.82 / 127.60 against 117.92 / 127.69 N/mm^2) differ by under 0.1 %.  The shift is about
    what a tooth 0.1 mm thinner at d_en gives (gamma_e at about x - 0.01); the report's tooth thickness
    allowances (-0.130/-0.190 and -0.240/-0.340 mm, section 6) do not fit both members, so the cause
    stays open (docs/rating.md 3.1)."""
    ours = kiss[where][name]
    assert ours == pytest.approx(printed, rel=rel)
    assert not _within_printed(ours, printed, 2)  # an honest list: these miss the printed digits


# --- 4. the permissible stresses' factors: FZG-C, STplus 11.1F, ISO 6336-2/-3:2019 (sheets 2, 9-12) --------
# Inputs of the listing: oil FVA-3A, nu_40 = 90.02 mm^2/s (sheet 2; printed "90." on sheet 11); flank Ra
# 0.3 um both (ARITHM_MITTENRAUHW_FL), which STplus prints as R_zH = 1.80 um (= 6 Ra); root R_zF = 20 um;
# n_1 = 1500 1/min, v = 5.749 m/s at the working pitch circle (sheet 9); 17CrNiMo6 case-hardened,
# sigma_Hlim 1510 N/mm^2 (STplus prints the product "Z_L*Z_R*Z_V (sigma_Hlim = 1200.)": C_ZL and C_ZR
# are clamped there, 0.91 and 0.08 either way); m_n = 4.5 mm.
FZG_C_FACTORS_PRINTED = [("Z_L", 0.960, 3), ("Z_v", 0.985, 3), ("Z_R", 1.037, 3), ("R_z10_um", 1.9, 1),
                         ("Z_L Z_R Z_v", 0.981, 3), ("Y_X", 1.000, 3), ("Y_RrelT", 0.957, 3)]


@pytest.fixture(scope="module")
def fzg_c_factors():
    from beveloid.rating import materials
    from beveloid.rating.strength import RA_TO_RZ, pitch_point_radii_mm

    pinion, wheel = _stplus_gears(FZG_C)
    *_, rho_red = pitch_point_radii_mm(iso.CylindricalPair(pinion, wheel, 14.0))
    c_zl, c_zr = iso.lubricant_constant(1510.0), iso.roughness_constant(1510.0)
    z_l, z_v = iso.lubricant_factor(c_zl, 90.02), iso.velocity_factor(c_zl, 5.749)
    z_r, rz10 = iso.roughness_factor(c_zr, RA_TO_RZ * 0.3, rho_red)
    eh = materials.MATERIALS["case-hardened"]
    return {"Z_L": z_l, "Z_v": z_v, "Z_R": z_r, "R_z10_um": rz10, "Z_L Z_R Z_v": z_l * z_r * z_v,
            "Y_X": iso.size_factor_bending(eh.size_group, 4.5), "Y_RrelT": iso.relative_surface_factor(eh.surface_group, 20.0)}


@pytest.mark.parametrize("name, printed, decimals", FZG_C_FACTORS_PRINTED, ids=[p[0] for p in FZG_C_FACTORS_PRINTED])
def test_stplus_fzg_c_lubricant_roughness_velocity_size_and_surface_factors(fzg_c_factors, name, printed, decimals):
    """FZG-C rated by STplus 11.1F to ISO 6336:2019: Z_L, Z_v, Z_R (with rho_red at the pitch point of the
    pair and R_z = 6 Ra), their product, Y_X and Y_RrelT round to the printed values."""
    ours = fzg_c_factors[name]
    assert _within_printed(ours, printed, decimals), f"{name}: ours {ours!r}, printed {printed}"

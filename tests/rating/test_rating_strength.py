"""The factors of the permissible stresses (beveloid/rating/strength.py, docs/rating.md 4.3; issue 57.7):
ISO 6336-2's Z_L, Z_v, Z_R from the lubricant, the speed and the flank roughness, ISO 6336-3's Y_X and
Y_RrelT, against hand computations; and K_Hbeta at the p90 of the tolerance box under load."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

from beveloid import assembly_errors, cli, ltca, rating, sweep
from beveloid.pair import Pair
from beveloid.rating import iso6336, materials, strength
from beveloid.rating.face_load import face_load
from beveloid.solver import Solver
from beveloid.spec import load_example, spec_from_dict, spec_to_dict

TORQUE = 800.0
CASE1_TEXT = (Path(__file__).resolve().parents[2] / "examples" / "case1.toml").read_text(encoding="utf-8")


def _pair(**sections):
    d = spec_to_dict(load_example("case1"))
    d["rating"]["K_v"] = 1.0  # the same loaded contact with and without a speed
    for name, values in sections.items():
        d.setdefault(name, {}).update(values)
    return Pair.from_spec(spec_from_dict(d))


@pytest.fixture(scope="module")
def plate():
    pair = _pair()
    options = rating.Options(ltca.Options(positions=2, tooth_model="plate"))
    return pair, options, ltca.analyze(pair, ltca.LoadCase(TORQUE), options.ltca, solver=Solver())


def _rate(plate, **sections):
    _, options, lt = plate
    return rating.analyze(_pair(**sections), ltca.LoadCase(TORQUE), options, ltca_result=lt)


def test_the_constants_of_iso_6336_2_are_continuous_at_their_clamps():
    """C_ZL = 0.83 below 850 MPa, sigma_Hlim/4375 + 0.6357 to 1200 MPa, 0.91 above; C_ZR = 0.15, 0.32 -
    0.0002 sigma_Hlim, 0.08: the linear parts meet the clamps (to ISO's four digits)."""
    assert iso6336.lubricant_constant(600.0) == 0.83 and iso6336.lubricant_constant(1500.0) == 0.91
    assert iso6336.lubricant_constant(850.0) == pytest.approx(0.83, abs=1e-4)
    assert iso6336.lubricant_constant(1200.0) == pytest.approx(0.91, abs=1e-4)
    assert iso6336.lubricant_constant(1000.0) == pytest.approx(1000.0 / 4375.0 + 0.6357)
    assert iso6336.roughness_constant(600.0) == 0.15 and iso6336.roughness_constant(1500.0) == 0.08
    assert iso6336.roughness_constant(850.0) == pytest.approx(0.15) and iso6336.roughness_constant(1200.0) == pytest.approx(0.08)
    assert iso6336.roughness_constant(1000.0) == pytest.approx(0.12)
    # nu_40 = 134/0.8 mm^2/s makes the bracket 2: Z_L = C_ZL + (1 - C_ZL) = 1; v = 10 m/s (32/v = 3.2) the
    # root 2: Z_v = C_Zv + (1 - C_Zv) = 1
    assert iso6336.lubricant_factor(0.85, 134.0 / 0.8) == pytest.approx(1.0)
    assert iso6336.velocity_factor(0.85, 10.0) == pytest.approx(1.0)
    z_r, rz10 = iso6336.roughness_factor(0.08, 3.0, 10.0)
    assert (z_r, rz10) == (pytest.approx(1.0), pytest.approx(3.0))


@pytest.mark.parametrize(("material", "m_n", "y_x"), [
    ("case-hardened", 6.0, 0.99), ("nitrided", 6.0, 0.99), ("nitrocarburised", 20.0, 0.85),
    ("case-hardened", 30.0, 0.8), ("through-hardened", 6.0, 0.994), ("nodular-cast-iron", 10.0, 0.97),
    ("through-hardened", 40.0, 0.85), ("grey-cast-iron", 6.0, 0.985), ("grey-cast-iron", 25.0, 0.7),
    ("case-hardened", 5.0, 1.0), ("grey-cast-iron", 2.0, 1.0)])
def test_the_size_factor_of_each_material(material, m_n, y_x):
    """Y_X of ISO 6336-3 (long life): 1.05 - 0.01 m_n for Eh, NT, NV (0.8 from 25 mm), 1.03 - 0.006 m_n
    for V and GGG perl. (0.85 from 30 mm), 1.075 - 0.015 m_n for GG (0.7 from 25 mm), 1 up to 5 mm."""
    assert iso6336.size_factor_bending(materials.MATERIALS[material].size_group, m_n) == pytest.approx(y_x)


@pytest.mark.parametrize(("material", "rz", "y_r"), [
    ("case-hardened", 20.0, 1.674 - 0.529 * 21.0 ** 0.1), ("through-hardened", 0.5, 1.120),
    ("nitrided", 20.0, 4.299 - 3.259 * 21.0 ** 0.0058), ("grey-cast-iron", 0.5, 1.025),
    ("case-hardened", 100.0, 1.674 - 0.529 * 41.0 ** 0.1)])
def test_the_relative_surface_factor_of_each_material(material, rz, y_r):
    assert iso6336.relative_surface_factor(materials.MATERIALS[material].surface_group, rz) == pytest.approx(y_r)


def test_the_factors_fade_to_their_static_value_over_the_life_curve():
    """ISO interpolates the permissible stress log-log between its static value (factors 1) and its
    reference value (factors whole): half-way in log N between N_static and the knee, half the exponent."""
    z = materials.Z_NT_EH_V  # 1e5 (static) .. 5e7 (knee)
    assert strength.life_weight(z, None) == 1.0 and strength.life_weight(z, 5e4) == 0.0
    assert strength.life_weight(z, 1e9) == 1.0
    assert strength.life_weight(z, math.sqrt(1e5 * 5e7)) == pytest.approx(0.5)


def _hand_pitch_point_rho_red(sec) -> float:
    """rho_red of a section's virtual cylindrical pair from the JSON alone: z1 = d1 cos(beta)/m_n,
    alpha_t, inv alpha_wt = inv alpha_t + 2 tan(alpha_n) (x1 + x2)/(z1 + z2), rho_i = d_bi tan(alpha_wt)/2."""
    mn, an, beta = sec["normal_module_mm"], math.radians(sec["normal_pressure_angle_deg"]), math.radians(sec["helix_angle_deg"])
    d1 = sec["reference_diameter_mm"]
    z1, z2 = d1 * math.cos(beta) / mn, sec["mate_teeth"]
    d2 = z2 * mn / math.cos(beta)
    at = math.atan(math.tan(an) / math.cos(beta))
    target = math.tan(at) - at + 2 * math.tan(an) * (sec["normal_profile_shift"] + sec["mate_normal_profile_shift"]) / (z1 + z2)
    awt = brentq(lambda a: math.tan(a) - a - target, 0.05, 1.4, xtol=1e-15)
    r1, r2 = d1 * math.cos(at) * math.tan(awt) / 2, d2 * math.cos(at) * math.tan(awt) / 2
    return r1 * r2 / (r1 + r2)


def test_a_vg68_oil_at_low_speed_lowers_s_h_by_the_hand_computed_factors(plate):
    """Case 1 (case-hardened MQ, sigma_Hlim 1500 MPa: C_ZL 0.91, C_ZR 0.08) with an ISO VG 68 oil, flanks
    of Ra 0.8 um (R_z = 6 Ra = 4.8 um) and 50 rpm: every S_H (ISO sections and local) is that of the dry,
    static rating times Z_L Z_v Z_R computed by hand here from the JSON's own virtual gears, and < 1."""
    dry = _rate(plate)
    oiled = _rate(plate, lubricant=dict(iso_vg=68, temperature_c=60.0), rating=dict(pinion_speed_rpm=50.0),
                  pinion=dict(roughness_ra_um=0.8), gear=dict(roughness_ra_um=0.8))
    out = oiled.to_json()
    d1 = out["pinion"]["sections"]["middle"]["reference_diameter_mm"]
    z_l = 0.91 + 4 * (1 - 0.91) / (1.2 + 134.0 / 68.0) ** 2
    v = math.pi * d1 * 50.0 / 60000.0
    z_v = 0.93 + 2 * (1 - 0.93) / math.sqrt(0.8 + 32.0 / v)
    for member in ("pinion", "gear"):
        rho_red = _hand_pitch_point_rho_red(out[member]["sections"]["middle"])
        z_r = (3.0 / (4.8 * (10.0 / rho_red) ** (1.0 / 3.0))) ** 0.08
        product = z_l * z_v * z_r
        assert 0.8 < product < 0.95
        reported = out[member]["strength_factors"]
        assert reported["Z_L"]["value"] == pytest.approx(z_l, rel=1e-12)
        assert reported["Z_v"]["value"] == pytest.approx(z_v, rel=1e-12)
        assert reported["Z_R"]["value"] == pytest.approx(z_r, rel=1e-9)
        assert reported["Z_R"]["inputs"]["rho_red_mm"] == pytest.approx(rho_red, rel=1e-9)
        for name, sec in oiled.members[member].sections.items():
            assert sec.safety_pitting_iso == pytest.approx(dry.members[member].sections[name].safety_pitting_iso * product,
                                                           rel=1e-9)
        assert oiled.members[member].safety_pitting == pytest.approx(dry.members[member].safety_pitting * product, rel=1e-9)
    assumptions = " ".join(oiled.verdict()["assumptions"])
    assert "Z_L = 1" not in assumptions and "Z_v = 1" not in assumptions and "Z_R = 1" not in assumptions
    dry_assumptions = " ".join(dry.verdict()["assumptions"])
    assert "Z_L = 1 (no oil viscosity" in dry_assumptions and "Z_v = 1 (no [rating] pinion_speed_rpm" in dry_assumptions


def test_module_6_gets_the_size_factor_and_a_root_roughness_its_surface_factor(plate):
    """Case 1 has m_n = 6 mm > 5: Y_X = 1.05 - 0.06 = 0.99 (case-hardened) lowers every S_F by 1 %; a root
    fillet of R_z 20 um (rougher than the reference test gear's ~10 um) gives Y_RrelT = 1.674 - 0.529 21^0.1."""
    r = _rate(plate, pinion=dict(root_roughness_rz_um=20.0))
    f = r.factors
    y_r = 1.674 - 0.529 * 21.0 ** 0.1
    assert y_r < 1.0
    for member, y in (("pinion", 0.99 * y_r), ("gear", 0.99)):
        for sec in r.members[member].sections.values():
            assert sec.safety_bending_iso * sec.sigma_F_mpa == pytest.approx(f.root_limit_mpa[member] * 2.0 * y, rel=1e-12)
        assert r.to_json()[member]["strength_factors"]["Y_X"]["value"] == pytest.approx(0.99)
    assumptions = r.verdict()["assumptions"]
    assert any(a.startswith("Y_RrelT = 1 on the gear (no root_roughness_rz_um") for a in assumptions)


def test_the_tolerance_box_p90_raises_k_h_beta_above_the_aligned_value():
    """rating.Options(tolerance_samples=8): eight error sets of the tolerance box about the aligned pair
    (tilts up to 0.05 / 0.02 deg), each a full LTCA through ltca.studies.box_results; each set's K_Hbeta is
    the face load of an LTCA at that set's errors (at the asked positions), the ISO sections take the sets' 90th
    percentile, which lies above the aligned pair's K_Hbeta at the same positions on both members, times the
    aligned pair's refinement between positions (its refined K_Hbeta over that)."""
    pair = _pair()
    half = {"dx_mm": 0.05, "dy_mm": 0.05, "dz_mm": 0.05, "vertical_deg": 0.05, "horizontal_deg": 0.02}
    base = ltca.Options(positions=4, tooth_model="plate")
    solver = Solver()
    aligned = rating.analyze(pair, ltca.LoadCase(TORQUE), rating.Options(base), solver=solver)
    boxed = rating.analyze(pair, ltca.LoadCase(TORQUE), rating.Options(base, tolerance_samples=8, tolerances=half),
                           solver=solver)
    box = boxed.tolerance_box
    assert box["sets"] == 8 and box["percentile"] == 90.0
    geom = pair.geometry
    draws = sweep.draw_errors(8, ranges=half, seed=0, nominal=assembly_errors.from_layout(np.zeros(5)))
    one = ltca.analyze(pair, ltca.LoadCase(TORQUE, errors=draws[3]), base, solver=solver)
    b = min(geom.pinion.face_width_mm, geom.gear.face_width_mm)
    for member in ("pinion", "gear"):
        per_set = box["members"][member]["K_H_beta"]
        assert per_set[3] == pytest.approx(face_load(one, geom, member, b).K_H_beta, rel=1e-9)
        p90 = float(np.percentile(per_set, 90))
        k_aligned = aligned.members[member].sections["middle"].K_H_beta
        assert box["members"][member]["nominal"] == pytest.approx(k_aligned)
        kh = aligned.loaded.positions_check["quantities"]["K_H_beta"][member]
        assert kh["all"] == pytest.approx(k_aligned)
        assert p90 > kh["asked"] and box["members"][member]["refinement_factor"] == pytest.approx(kh["all"] / kh["asked"])
        for name, sec in boxed.members[member].sections.items():
            assert sec.K_H_beta == pytest.approx(p90 * kh["all"] / kh["asked"])
            assert sec.safety_bending_iso < aligned.members[member].sections[name].safety_bending_iso
    json_box = boxed.to_json()["tolerance_box"]
    assert json_box["members"]["pinion"]["p90"] == pytest.approx(float(np.percentile(box["members"]["pinion"]["K_H_beta"], 90)))
    assert boxed.verdict()["assumptions"][0].startswith("K_H_beta at the p90 of 8 error sets of the tolerance box")
    assert aligned.verdict()["assumptions"][0].startswith("K_H_beta of the aligned pair only")


@pytest.mark.parametrize(("edit", "flags", "fragment"), [
    (("teeth = 29 ", "roughness_rz_um = -1.0\nteeth = 29 "), (), "pinion.roughness_rz_um = -1"),
    (("teeth = 45 ", "root_roughness_rz_um = 500.0\nteeth = 45 "), (), "gear.root_roughness_rz_um = 500"),
    (("[misalignment]", "[rating]\ntolerance_samples = 2.5\n[misalignment]"), (), "rating.tolerance_samples = 2.5"),
    (None, ("--samples", "-1"), "--samples = -1: must be an integer from 0"),
    (None, ("--samples", "2", "--tolerances", "vertical=9"), "--tolerances vertical=9: must be a number from 0 to 5"),
])
def test_bad_strength_and_box_input_is_one_line_exit_2(capsys, tmp_path, edit, flags, fragment):
    text = CASE1_TEXT if edit is None else CASE1_TEXT.replace(*edit, 1)
    p = tmp_path / "bad.toml"
    p.write_text(text)
    rc = cli.main(["rating", str(p), "--torque-nm", "100", "--positions", "2", "--tooth-model", "plate", *flags])
    out, err = capsys.readouterr()
    assert rc == 2 and out == ""
    assert len(err.strip().splitlines()) == 1 and fragment in err and "Traceback" not in err

"""A parallel helical pair (the FZG H501 teeth, issue 58's 'other published cases'): a line contact is
entrained only across its line, so ISO/TR 14179-2's sum velocity 2 v_t sin(alpha_wt) is the sum
velocity's part across the line, and the radius is the relative one across it (the normal section)."""
import math

import numpy as np
import pytest

from beveloid import ltca, tribology
from beveloid.pair import Pair
from beveloid.spec import spec_from_dict
from beveloid.tribology.analysis import pitch_point

MN, Z1, Z2, BETA, A, B, T, N = 3.5, 20, 30, math.radians(15.0), 91.5, 23.0, 100.0, 1000.0


@pytest.fixture(scope="module")
def helical(cases):
    return Pair.from_spec(spec_from_dict(cases.spec_dict(
        pair=dict(normal_module_mm=MN),
        pinion=dict(teeth=Z1, helix_angle_deg=15.0, profile_shift=0.1809 * math.cos(BETA), face_width_mm=B, roughness_ra_um=0.6),
        gear=dict(teeth=Z2, face_width_mm=B, roughness_ra_um=0.6))))


def textbook():
    """The helical pair's pitch point from the textbook formulas (independent of the code)."""
    alpha_t = math.atan(math.tan(math.radians(20.0)) / math.cos(BETA))
    a0 = MN * (Z1 + Z2) / (2 * math.cos(BETA))
    alpha_wt = math.acos(a0 * math.cos(alpha_t) / A)
    beta_b = math.asin(math.sin(BETA) * math.cos(math.radians(20.0)))
    rw1 = A * Z1 / (Z1 + Z2)
    rb1 = MN * Z1 / (2 * math.cos(BETA)) * math.cos(alpha_t)
    rho_t = rw1 * math.sin(alpha_wt) * (A - rw1) * math.sin(alpha_wt) / (A * math.sin(alpha_wt))
    w1 = N * math.pi / 30
    return dict(alpha_wt=alpha_wt, beta_b=beta_b, f_bt=T * 1e3 / rb1, v_sum=2 * w1 * rw1 * 1e-3 * math.sin(alpha_wt),
                rho_t=rho_t, rho_n=rho_t / math.cos(beta_b))


@pytest.mark.parametrize("flank", ["left", "right"])
def test_pitch_point_is_isos_sum_velocity_and_the_normal_radius(helical, flank):
    tb = textbook()
    pp = pitch_point(helical.geometry, flank)
    assert pp.sum_velocity_m_s * N * math.pi / 30 == pytest.approx(tb["v_sum"], rel=1e-4)
    assert pp.reduced_radius_mm == pytest.approx(tb["rho_n"], rel=1e-4)


def test_global_friction_is_iso_tr_14179_2_of_the_helical_pair(helical):
    """F_bn / rho_n = F_bt / rho_t: ISO's transverse quantities; the full projected sum velocity (16 %
    faster here) and the radius in its direction would give a coefficient 9 % lower."""
    tb = textbook()
    result = ltca.analyze(helical, ltca.LoadCase(T), ltca.Options(flank="left", tooth_model="plate", positions=5))
    got = tribology.evaluate(result, helical, N)
    eta = got.dynamic_viscosity_mpa_s
    expected = (0.048 * (tb["f_bt"] / B / (tb["v_sum"] * tb["rho_t"])) ** 0.2 * eta ** -0.05 * 0.6 ** 0.25
                * helical.spec.lubricant.lubricant_factor_xl)
    assert got.friction_coefficient_global == pytest.approx(expected, rel=1e-4)


def test_line_contact_cells_are_entrained_across_their_line(helical):
    """In the line-contact cells the film takes the sum velocity's part across the line and the radius
    across it: the line formula with those reproduces the cell's film, and the full speed is much faster."""
    result = ltca.analyze(helical, ltca.LoadCase(T), ltca.Options(flank="left", tooth_model="plate", positions=5))
    got = tribology.evaluate(result, helical, N)
    c = got.cells
    j, k = np.argwhere(np.asarray(c.line_contact))[0]
    loaded = np.asarray(c.loaded[j, k])
    w = N * math.pi / 30
    across = np.asarray(c.sum_across[j, k])[loaded] * w
    full = np.linalg.norm(np.asarray(c.sum_velocity[j, k])[loaded], axis=-1) * w
    assert np.all(full > 1.1 * across)  # the helix's lengthwise part is a real share of it
    e_prime = 2.0 * tribology.Prepared(result, helical).e_star_mpa * 1e6
    lub = tribology.lubricant.Lubricant.from_spec(helical.spec.lubricant)
    hc, hm = tribology.laws.line_contact_film(
        0.5 * across, np.asarray(c.radius_across_mm[j, k])[loaded], np.asarray(c.line_load_n_per_mm[j, k])[loaded],
        lub.dynamic_viscosity_pa_s, lub.pressure_viscosity_1_per_pa, e_prime)
    np.testing.assert_allclose(np.asarray(got.cell_film_central_um[j, k])[loaded], hc, rtol=1e-12)
    np.testing.assert_allclose(np.asarray(got.cell_film_min_um[j, k])[loaded], hm, rtol=1e-12)

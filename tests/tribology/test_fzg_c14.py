"""The parallel-axis limit against the published FZG C14 calculation (issue 58): the spur pair as a
beveloid with shaft and cone angles of 1e-4 deg, 200 N m at 1500 rpm, mineral ISO VG 32 at 60 C."""
import math

import numpy as np
import pytest
from scipy.optimize import brentq

from beveloid import tribology
from beveloid.pair import Pair
from beveloid.spec import spec_from_dict
from beveloid.tribology import laws

PUBLISHED_LOSS_W = 274.37
PUBLISHED_MU = 0.0449
PUBLISHED_CENTRAL_UM = (0.15, 0.24)
PUBLISHED_MIN_UM = (0.13, 0.20)


@pytest.fixture(scope="module")
def tri(fzg_ltca, fzg_pair):
    return tribology.evaluate(fzg_ltca, fzg_pair, 1500.0)


def spur_pitch_point():
    """The C14 pair's pitch-point data from the textbook spur formulas (independent of the code)."""
    mn, z1, z2, x1, x2, alpha = 4.5, 16, 24, 0.1817, 0.1715, math.radians(20.0)
    inv = lambda t: math.tan(t) - t  # noqa: E731
    aw = brentq(lambda t: inv(t) - (inv(alpha) + 2 * math.tan(alpha) * (x1 + x2) / (z1 + z2)), 0.1, 0.7)
    a = mn * (z1 + z2) / 2 * math.cos(alpha) / math.cos(aw)
    rw1 = a * z1 / (z1 + z2)
    rb1 = mn * z1 / 2 * math.cos(alpha)
    rho1, rho2 = rw1 * math.sin(aw), (a - rw1) * math.sin(aw)
    w1 = 1500 * math.pi / 30
    return dict(f_bt=200e3 / rb1, v_sum=2 * w1 * rw1 * 1e-3 * math.sin(aw), rho=rho1 * rho2 / (rho1 + rho2))


def test_input_power_and_loss_within_5_percent(tri):
    assert tri.input_power_w == pytest.approx(31415.9, abs=0.05)
    assert tri.friction_coefficient_mean == pytest.approx(0.0449, rel=1e-12)  # the fixed coefficient
    assert abs(tri.mesh_power_loss_w / PUBLISHED_LOSS_W - 1) < 0.05


def test_global_friction_is_iso_tr_14179_2_at_the_pitch_point(tri):
    """The global coefficient equals ISO/TR 14179-2's formula with the spur pitch-point data."""
    pp = spur_pitch_point()
    expected = 0.048 * (pp["f_bt"] / 14.0 / (pp["v_sum"] * pp["rho"])) ** 0.2 * 13.28 ** -0.05 * 0.355 ** 0.25 * 0.85
    assert tri.friction_coefficient_global == pytest.approx(expected, rel=2e-4)  # eta 13.2799 against 13.28


def test_global_friction_to_the_printed_digits_with_the_published_oil_factor(fzg_ltca, cases):
    """The published calculation prints X_L "0.85" for its mineral oil; its lubricant table holds 0.846
    (docs/tribology.md, 'The FZG C14 check'). With that input, and nothing else changed, ISO/TR 14179-2's
    coefficient equals the published 0.0449 to its printed digits and P mu H_VL its loss 274.37 W."""
    pair = Pair.from_spec(spec_from_dict(cases.spec_dict(lubricant=dict(lubricant_factor_xl=0.846))))
    got = tribology.evaluate(fzg_ltca, pair, 1500.0)
    assert round(got.friction_coefficient_global, 4) == PUBLISHED_MU
    # the loss the published calculation states: input power x mu x its H_VL (Wimmer, 0.1946)
    assert 31415.9 * got.friction_coefficient_global * 0.1946 == pytest.approx(PUBLISHED_LOSS_W, rel=1e-3)


def test_global_friction_is_proportional_to_the_oil_factor(tri, fzg_ltca, cases):
    """X_L is the formula's last factor: at the issue's rounded X_L 0.85 the coefficient prints 0.0451."""
    pair = Pair.from_spec(spec_from_dict(cases.spec_dict(lubricant=dict(lubricant_factor_xl=0.846))))
    got = tribology.evaluate(fzg_ltca, pair, 1500.0)
    assert tri.friction_coefficient_global / got.friction_coefficient_global == pytest.approx(0.85 / 0.846, rel=1e-12)
    assert round(tri.friction_coefficient_global, 4) == 0.0451


def test_line_contact_film_at_the_pitch_point(tri, fzg_ltca):
    """Near the pitch point, where one pair carries the whole load, the film is the line contact's
    (Dowson-Toyoda central, Dowson-Higginson minimum) with the spur pair's pitch-point radius and
    entraining speed and the load spread over the face: the pair is a line contact (the LTCA's rule)."""
    pp = spur_pitch_point()
    j = int(np.argmin(np.abs(fzg_ltca.pinion_angle - 0.0)))  # the position nearest the pitch point
    k = int(np.nanargmax(fzg_ltca.pair_load_n[j]))
    e_prime, eta, alpha = 206e9 / (1 - 0.09), 13.28e-3, 20.47e-9
    rx = pp["rho"] * 1e-3
    u = eta * pp["v_sum"] / 2 / (e_prime * rx)
    w = fzg_ltca.pair_load_n[j, k] / 14e-3 / (e_prime * rx)
    hc = 3.06 * u ** 0.69 * (alpha * e_prime) ** 0.56 * w ** -0.10 * rx * 1e6
    hm = 2.65 * u ** 0.70 * (alpha * e_prime) ** 0.54 * w ** -0.13 * rx * 1e6
    # the position is within half a step of the pitch point (radius and speed a few per cent off), and
    # the pair's film is its thinnest cell's (the line load peaks at the face ends)
    assert tri.cells.line_contact[j, k]
    assert tri.pair_film_thickness_central_um[j, k] == pytest.approx(hc, rel=0.05)
    assert tri.pair_film_thickness_min_um[j, k] == pytest.approx(hm, rel=0.05)


def test_film_within_15_percent_of_the_published_range(tri):
    for got, (lo, hi) in ((tri.pair_film_thickness_central_um, PUBLISHED_CENTRAL_UM),
                          (tri.pair_film_thickness_min_um, PUBLISHED_MIN_UM)):
        assert np.nanmin(got) >= 0.85 * lo and np.nanmax(got) <= 1.15 * hi
        # and the range's ends themselves within 15 %
        assert abs(np.nanmin(got) / lo - 1) < 0.15 and abs(np.nanmax(got) / hi - 1) < 0.15


def test_ohlendorf_loss_factor_of_the_pair():
    """ISO/TR 14179-2's H_V (Ohlendorf) with the C14 addendum contact ratios gives the published 0.1986."""
    pp_rb1, pp_rb2 = 36 * math.cos(math.radians(20)), 54 * math.cos(math.radians(20))
    ra1, ra2 = 36 + 4.5 * (1 + 0.1817), 54 + 4.5 * (1 + 0.1715)
    aw = math.acos((36 + 54) * math.cos(math.radians(20)) / 91.5)
    pb = math.pi * 4.5 * math.cos(math.radians(20))
    e1 = (math.sqrt(ra1 ** 2 - pp_rb1 ** 2) - pp_rb1 * math.tan(aw)) / pb
    e2 = (math.sqrt(ra2 ** 2 - pp_rb2 ** 2) - pp_rb2 * math.tan(aw)) / pb
    assert laws.ohlendorf_hv(16, 1.5, e1, e2) == pytest.approx(0.1986, abs=6e-4)

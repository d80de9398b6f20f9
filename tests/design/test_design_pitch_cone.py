"""Tests for beveloid.design (direct / indirect pitch-cone design) and beveloid.design.report.

The oracle for the residual identities is an independent plain-numpy transcription of the
*printed* Eqs 12-27 (as read in /work/shared/paper/equations.md), not the generated kernels.
The transverse pressure angles, which the paper does not print, are transcribed from the
tilted rack of Eqs 1-3: tan(alpha_P) = (tan(alpha_n) cos(gamma) +- sin(beta) sin(gamma)) / cos(beta)
(+ left flank, - right flank).
"""
from __future__ import annotations

import argparse
import copy
import dataclasses
import json
import math
import tomllib
from decimal import Decimal
from pathlib import Path

import numpy as np
import pytest
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st

from beveloid.cli import design as cli_design
from beveloid.design import DesignError, DesignResult, MemberDesign, design, indirect_design
from beveloid.design import TABLE1_ROWS, design_json, format_table1
from beveloid.errors import UserError
from beveloid.generated import design_equations as kernels
from beveloid.spec import SpecError, load_spec, spec_from_dict, spec_to_dict

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"
# the paper's printed Table 1, shipped with the package (beveloid/data/) for `beveloid paper`
TABLE1 = tomllib.loads((Path(__file__).resolve().parents[2] / "beveloid" / "data" / "table1.toml").read_text())

deg, rad = math.degrees, math.radians
sin, cos, tan = math.sin, math.cos, math.tan
REL = 1e-9


@pytest.fixture(scope="module")
def case1() -> DesignResult:
    return design(load_spec(EXAMPLES / "case1.toml"))


@pytest.fixture(scope="module")
def case2() -> DesignResult:
    return design(load_spec(EXAMPLES / "case2.toml"))


def base_dict() -> dict:
    return spec_to_dict(load_spec(EXAMPLES / "case1.toml"))


def modified(**changes) -> dict:
    """Case 1 as a dict with ``section__key=value`` changes."""
    d = copy.deepcopy(base_dict())
    for k, v in changes.items():
        section, key = k.split("__")
        d[section][key] = v
    return d


# ---------------------------------------------------------------------------
# Independent oracle: the printed equations
# ---------------------------------------------------------------------------


def inv(a: float) -> float:
    return tan(a) - a


def tan_transverse(alpha: float, beta: float, gamma: float, sigma: int) -> float:
    """Tilted rack (Eqs 1-3): transverse pressure angle of flank sigma (+1 left, -1 right)."""
    return (tan(alpha) * cos(gamma) + sigma * sin(beta) * sin(gamma)) / cos(beta)


def close(a: float, b: float, floor: float = 1.0, rel: float = REL) -> bool:
    return math.isfinite(a) and math.isfinite(b) and abs(a - b) <= rel * max(abs(a), abs(b), floor)


def tangency_rel(r: DesignResult) -> float:
    """Relative tolerance for quantities that go through eta = beta_w1 + beta_w2 (Eqs 10-17, E).

    1e-9, except close to the end of the tangency range (E -> 0): there eta = arccos(X) with X -> 1
    (Eq 16), so sin(eta), E and every relation with E/S carry a relative rounding error of about
    eps / sin^2(eta) -- a property of the kernels' arccos form, not of the design.  Measured:
    1.2e-9 at sin^2(eta) = 4.6e-7 (E = 1 mm); allowed: 64 eps / sin^2(eta).
    """
    eta = r.pinion.working_helix_angle + r.gear.working_helix_angle
    return max(REL, 64 * np.finfo(float).eps / sin(eta) ** 2)


def check_identities(r: DesignResult) -> list[str]:
    """Every printed Eq 12-27 (and the tangency of Eqs 8-11 at the pitch point); returns failures."""
    bad: list[str] = []
    rel_t = tangency_rel(r)

    def expect(name: str, a: float, b: float, floor: float = 1.0, rel: float = REL) -> None:
        if not close(a, b, floor, rel):
            bad.append(f"{name}: {a!r} != {b!r} (rel {rel:.1e})")

    p, g = r.pinion, r.gear
    E, delta, an, anw, mn = r.offset_mm, r.shaft_angle, r.normal_pressure_angle, r.working_normal_pressure_angle, \
        r.normal_module_mm
    gw1, gw2, bw1, bw2 = p.working_cone_angle, g.working_cone_angle, p.working_helix_angle, g.working_helix_angle
    rw1, rw2 = p.working_pitch_radius_mm, g.working_pitch_radius_mm
    # all finite
    for m in (p, g):
        for f in MemberDesign.__dataclass_fields__:
            v = getattr(m, f)
            if isinstance(v, float) and not math.isfinite(v):
                bad.append(f"{m.name}.{f} not finite")
    S = math.sqrt(sin(delta) ** 2 - sin(gw1) ** 2 - sin(gw2) ** 2 - 2 * sin(gw1) * sin(gw2) * cos(delta))
    # Eq 12
    expect("Eq 12", rw1, E * cos(gw1) * sin(delta) / S - rw2 * cos(gw1) / cos(gw2), floor=rw1, rel=rel_t)
    # Eqs 13, 14
    d1 = (E * (sin(delta) ** 2 - sin(gw1) ** 2 - sin(gw1) * sin(gw2) * cos(delta)) / (sin(gw1) * sin(delta) * S)
          - rw2 / (sin(gw1) * cos(gw2)))
    d2 = (E * (sin(delta) ** 2 - sin(gw2) ** 2 - sin(gw1) * sin(gw2) * cos(delta)) / (sin(gw2) * sin(delta) * S)
          - rw1 / (sin(gw2) * cos(gw1)))
    expect("Eq 13", p.mounting_distance_mm, d1, floor=rw1, rel=rel_t)
    expect("Eq 14", g.mounting_distance_mm, d2, floor=rw2, rel=rel_t)
    # Eq 16 ("+" form) and Eq 17
    expect("Eq 16", cos(bw1 + bw2), tan(gw1) * tan(gw2) + cos(delta) / (cos(gw1) * cos(gw2)))
    expect("Eq 17", E, (rw1 * cos(gw2) + rw2 * cos(gw1)) * sin(bw1 + bw2) / sin(delta), floor=E, rel=rel_t)
    # Eqs 8-11 at the pitch point: one point, a common normal, cos(eta) = tau1 . tau2 (Eq 15)
    th1, th2 = p.pitch_point_angle, g.pitch_point_angle
    dw1, dw2 = p.working_mounting_distance_mm, g.working_mounting_distance_mm
    expect("d_w1 = r_w1 / tan(gamma_w1) - d1", dw1, rw1 / tan(gw1) - p.mounting_distance_mm, floor=rw1, rel=rel_t)
    expect("d_w2 = r_w2 / tan(gamma_w2) - d2", dw2, rw2 / tan(gw2) - g.mounting_distance_mm, floor=rw2, rel=rel_t)

    def to_f(v):  # gear frame -> fixed frame (rotation of Eq 33)
        return np.array([v[0], cos(delta) * v[1] + sin(delta) * v[2], -sin(delta) * v[1] + cos(delta) * v[2]])

    P1 = np.array([rw1 * cos(th1), rw1 * sin(th1), dw1])
    P2 = np.array([E, 0.0, 0.0]) + to_f(np.array([rw2 * cos(th2), rw2 * sin(th2), dw2]))
    scale = max(rw1, rw2, abs(dw1), abs(dw2))
    for k in range(3):
        expect(f"Eq 10 pitch point component {k}", P1[k], P2[k], floor=scale, rel=rel_t)
    n1 = np.array([cos(th1) * cos(gw1), sin(th1) * cos(gw1), -sin(gw1)])
    n2 = to_f(np.array([cos(th2) * cos(gw2), sin(th2) * cos(gw2), -sin(gw2)]))
    expect("Eq 11 common normal", abs(float(n1 @ n2)), 1.0, rel=rel_t)
    t1 = np.array([sin(gw1) * cos(th1), sin(gw1) * sin(th1), cos(gw1)])
    t2 = to_f(np.array([sin(gw2) * cos(th2), sin(gw2) * sin(th2), cos(gw2)]))
    expect("Eq 15 cos(eta) = tau1 . tau2", float(t1 @ t2), cos(bw1 + bw2), rel=rel_t)
    # Eq 23 (three forms), Eqs 22, 24, 25, 26 for both members
    xi_n = cos(anw) / cos(an)
    expect("Eq 23 xi_n", r.normal_angular_factor, xi_n)
    for m in (p, g):
        b, gm, bw, gw, xt = m.helix_angle, m.cone_angle, m.working_helix_angle, m.working_cone_angle, \
            m.transverse_angular_factor
        r_ref, r_w = m.reference_pitch_radius_mm, m.working_pitch_radius_mm
        expect(f"{m.name} r = N m_n / (2 cos beta)", r_ref, m.teeth * mn / (2 * cos(b)), floor=r_ref)
        expect(f"Eq 22 {m.name} xi_t = r / r_w", xt, r_ref / r_w)
        m_nw = 2 * r_w * cos(bw) / m.teeth
        expect(f"Eq 23 {m.name} xi_n = m_n / m_nw", xi_n, mn / m_nw)
        expect(f"Eq 23 {m.name} xi_n = xi_t cos b / cos bw", xi_n, xt * cos(b) / cos(bw))
        tPL, tPR = tan_transverse(an, b, gm, +1), tan_transverse(an, b, gm, -1)
        tPwL, tPwR = tan_transverse(anw, bw, gw, +1), tan_transverse(anw, bw, gw, -1)
        expect(f"{m.name} alpha_PL", m.transverse_pressure_angle_left, math.atan(tPL))
        expect(f"{m.name} alpha_PR", m.transverse_pressure_angle_right, math.atan(tPR))
        expect(f"{m.name} alpha_PwL (working rack)", m.working_transverse_pressure_angle_left, math.atan(tPwL))
        expect(f"{m.name} alpha_PwR (working rack)", m.working_transverse_pressure_angle_right, math.atan(tPwR))
        expect(f"Eq 22 {m.name} left", xt, cos(math.atan(tPwL)) / cos(math.atan(tPL)))
        expect(f"Eq 22 {m.name} right", xt, cos(math.atan(tPwR)) / cos(math.atan(tPR)))
        expect(f"Eq 24 {m.name}", tan(gw), 2 * tan(an) * sin(gm) / cos(b) / (xt * (tPwR + tPwL)))
        expect(f"Eq 25a {m.name}", sin(gw), sin(gm) * tan(an) / (xi_n * tan(anw)))
        expect(f"Eq 25b {m.name}", sin(gw), sin(gm) * sin(an) / sin(anw))
        expect(f"Eq 26 {m.name}", sin(bw), sin(b) * cos(gm) / (xi_n * cos(gw)))
        # Eqs 19, 20 per member
        expect(f"Eq 19 {m.name}", tan(m.fpd_angle_left), tan(bw) * sin(anw) + tan(gw) * cos(anw) / cos(bw))
        expect(f"Eq 20 {m.name}", tan(m.fpd_angle_right), tan(bw) * sin(anw) - tan(gw) * cos(anw) / cos(bw))
    expect("Eq 18 left", r.fpd_angle_left, p.fpd_angle_left + g.fpd_angle_left)
    expect("Eq 18 right", r.fpd_angle_right, p.fpd_angle_right + g.fpd_angle_right)
    # Eq 27 (printed, with the result's pressure angles)
    lhs = 2 * tan(an) * (p.profile_shift * cos(p.cone_angle) / cos(p.helix_angle)
                         + g.profile_shift * cos(g.cone_angle) / cos(g.helix_angle))
    rhs = sum(m.teeth / 2 * (inv(m.working_transverse_pressure_angle_left)
                             + inv(m.working_transverse_pressure_angle_right)
                             - inv(m.transverse_pressure_angle_left) - inv(m.transverse_pressure_angle_right))
              for m in (p, g))
    expect("Eq 27", lhs, rhs)
    return bad


# ---------------------------------------------------------------------------
# Table 1
# ---------------------------------------------------------------------------


def computed_table1(r: DesignResult) -> dict:
    out = {"pair": {"delta_deg": deg(r.shaft_angle), "E_mm": r.offset_mm, "xi_L_deg": deg(r.fpd_angle_left),
                    "xi_R_deg": deg(r.fpd_angle_right)}}
    for m in (r.pinion, r.gear):
        out[m.name] = {
            "mn_mm": r.normal_module_mm, "alpha_n_deg": deg(r.normal_pressure_angle), "N": m.teeth,
            "gamma_deg": deg(m.cone_angle), "beta_deg": deg(m.helix_angle), "hand": m.hand,
            "x_t": m.profile_shift, "W_mm": m.face_width_mm, "xi_t": m.transverse_angular_factor,
            "d_mm": m.mounting_distance_mm, "gamma_w_deg": deg(m.working_cone_angle),
            "beta_w_deg": deg(m.working_helix_angle),
        }
    return out


def table1_rows(case: str):
    for section in ("pair", "pinion", "gear"):
        for key, printed in TABLE1[case][section].items():
            yield section, key, printed


def matches_printed(value, printed: str) -> bool:
    if not isinstance(value, (int, float)):
        return value == printed
    unit = Decimal(1).scaleb(Decimal(printed).as_tuple().exponent)  # one unit of the last printed digit
    return abs(Decimal(repr(float(value))) - Decimal(printed)) <= unit


@pytest.mark.parametrize("case", ["case1", "case2"])
def test_table1_every_printed_value(case, case1, case2):
    """Every printed value of Table 1 is reproduced to +-1 in its last printed digit (both cases)."""
    result = {"case1": case1, "case2": case2}[case]
    assert result.spec == load_spec(ROOT / TABLE1[case]["spec"])
    values = computed_table1(result)
    mismatches = [(s, k, values[s][k], p) for s, k, p in table1_rows(case) if not matches_printed(values[s][k], p)]
    # No known differences: case 2 (incl. gear gamma_w 0.7496 and d 10368) matches as well.
    assert mismatches == []
    assert sum(1 for _ in table1_rows(case)) == 4 + 2 * 12


def test_case1_chain_values_to_more_digits(case1):
    """The chain's own case 1 values (more digits than the paper)."""
    r, p, g = case1, case1.pinion, case1.gear
    assert deg(r.working_normal_pressure_angle) == pytest.approx(21.24962105784, abs=1e-10)
    expected = [
        (p.transverse_angular_factor, 0.990357, 1e-6), (g.transverse_angular_factor, 0.991549, 1e-6),
        (p.mounting_distance_mm, 2687.714, 1e-3), (g.mounting_distance_mm, 10297.010, 1e-3),
        (deg(p.working_cone_angle), 1.88732, 1e-5), (deg(g.working_cone_angle), 0.754942, 1e-6),
        (deg(p.working_helix_angle), 23.19898, 1e-5), (deg(g.working_helix_angle), -10.46858, 1e-5),
        (deg(g.helix_angle), -10.38215, 1e-5), (g.profile_shift, 0.192725, 1e-6),
        (deg(r.fpd_angle_left), 7.570207, 1e-6), (deg(r.fpd_angle_right), 2.408103, 1e-6),
    ]
    for value, want, tol in expected:
        assert value == pytest.approx(want, abs=tol)
    assert abs(r.offset_residual_mm) < 1e-11
    assert r.notes == ()


@pytest.mark.parametrize("case", ["case1", "case2"])
def test_identities_table1_cases(case, case1, case2):
    r = {"case1": case1, "case2": case2}[case]
    assert check_identities(r) == []


def test_result_fields(case1):
    r = case1
    assert r.procedure == "direct"
    assert r.member("pinion") is r.pinion and r.member("gear") is r.gear and r.member(2) is r.gear
    with pytest.raises(KeyError):
        r.member("wheel")
    assert r.offset_mm == 229.0 and r.normal_module_mm == 6.0
    assert r.shaft_angle == pytest.approx(rad(13)) and r.normal_pressure_angle == pytest.approx(rad(20))
    p = r.pinion
    assert p.rack_shift_mm == pytest.approx(0.15 * 6 * cos(rad(2)) / cos(rad(23)))
    assert p.cutter_addendum_mm == pytest.approx(1.25 * 6)
    assert (p.face_width_mm, r.gear.face_width_mm) == (50.0, 60.0)
    assert (p.hand, r.gear.hand) == ("RH", "LH")
    assert p.addendum_coefficient == 1.0 and p.reference_section_offset_mm == 0.0
    with pytest.raises(dataclasses_frozen_error()):
        r.pinion.teeth = 3  # type: ignore[misc]


def dataclasses_frozen_error():
    import dataclasses

    return dataclasses.FrozenInstanceError


# ---------------------------------------------------------------------------
# Indirect design
# ---------------------------------------------------------------------------


def assert_round_trip(r: DesignResult) -> None:
    """direct -> working data -> indirect -> reference data -> direct."""
    ri = indirect_design(r.spec, r.working_normal_pressure_angle, r.pinion.working_cone_angle,
                         r.gear.working_cone_angle, r.pinion.working_helix_angle)
    assert ri.procedure == "indirect"
    s, si = r.spec, ri.spec
    rel_t = tangency_rel(r)
    assert close(si.pair.offset_mm, s.pair.offset_mm, rel=rel_t)
    assert close(si.pinion.cone_angle_deg, s.pinion.cone_angle_deg)
    assert close(si.gear.cone_angle_deg, s.gear.cone_angle_deg)
    assert close(si.pinion.helix_angle_deg, s.pinion.helix_angle_deg)
    assert close(ri.gear.helix_angle, r.gear.helix_angle)
    assert close(ri.gear.profile_shift, r.gear.profile_shift)
    assert close(ri.gear.mounting_distance_mm, r.gear.mounting_distance_mm, floor=r.gear.working_pitch_radius_mm,
                 rel=rel_t)
    assert check_identities(ri) == []
    r2 = design(si)
    assert close(r2.working_normal_pressure_angle, r.working_normal_pressure_angle)
    assert close(r2.gear.helix_angle, r.gear.helix_angle)
    assert close(r2.gear.profile_shift, r.gear.profile_shift)


@pytest.mark.parametrize("case", ["case1", "case2"])
def test_indirect_round_trip_table1(case, case1, case2):
    assert_round_trip({"case1": case1, "case2": case2}[case])


def test_indirect_from_dict_without_reference_keys(case1):
    d = base_dict()
    del d["pair"]["offset_mm"], d["pinion"]["cone_angle_deg"], d["pinion"]["helix_angle_deg"]
    del d["gear"]["cone_angle_deg"]
    ri = indirect_design(d, case1.working_normal_pressure_angle, case1.pinion.working_cone_angle,
                         case1.gear.working_cone_angle, case1.pinion.working_helix_angle)
    assert ri.offset_mm == pytest.approx(229.0, rel=1e-12)
    assert deg(ri.pinion.cone_angle) == pytest.approx(2.0, rel=1e-12)
    assert deg(ri.pinion.helix_angle) == pytest.approx(23.0, rel=1e-12)
    assert deg(ri.gear.cone_angle) == pytest.approx(0.8, rel=1e-12)


# ---------------------------------------------------------------------------
# Property tests over the domain
# ---------------------------------------------------------------------------


@st.composite
def pair_data(draw):
    return dict(
        mn=draw(st.floats(1.0, 10.0)), an=draw(st.floats(15.0, 25.0)),
        N1=draw(st.integers(12, 100)), N2=draw(st.integers(12, 100)),
        delta=draw(st.floats(3.0, 45.0)), g1=draw(st.floats(0.2, 8.0)), g2=draw(st.floats(0.2, 8.0)),
        b1=draw(st.floats(-45.0, 45.0)), x1=draw(st.floats(-0.3, 0.6)),
        dalpha=draw(st.floats(-1.0, 2.0)),  # alpha_nw0 - alpha_n (deg): keeps x_t2 moderate
        fallback_E=draw(st.floats(1.0, 2000.0)),
    )


def spec_dict(v: dict, E: float) -> dict:
    return {
        "pair": {"normal_module_mm": v["mn"], "normal_pressure_angle_deg": v["an"], "shaft_angle_deg": v["delta"],
                 "offset_mm": E},
        "pinion": {"teeth": v["N1"], "cone_angle_deg": v["g1"], "helix_angle_deg": v["b1"],
                   "profile_shift": v["x1"], "face_width_mm": 8 * v["mn"]},
        "gear": {"teeth": v["N2"], "cone_angle_deg": v["g2"], "face_width_mm": 10 * v["mn"]},
    }


def assert_good_error(err: DesignError) -> None:
    msg = str(err)
    assert "\n" not in msg and msg.strip() == msg
    assert "nan" not in msg.lower().split()
    assert ("increase" in msg or "reduce" in msg), msg
    assert err.keys and all("." in k or k.endswith("angle") or k == "alpha_nw" for k in err.keys)
    assert any(k in msg for k in err.keys), msg
    assert isinstance(err, UserError) and isinstance(err, ValueError)


@settings(max_examples=60, deadline=None)
@given(pair_data())
@example(dict(mn=5.0, an=15.0, N1=12, N2=29, delta=4.0, g1=4.0, g2=0.5, b1=0.0, x1=0.0, dalpha=0.0,
              fallback_E=1.0))  # E = 1 mm: near the end of the tangency range (sin^2 eta = 4.6e-7)
# delta = gamma1 + gamma2 and alpha_nw0 = alpha_n: E0 is the round-off (~1e-6 mm) of a zero offset, where
# Eq 17 only touches E (a double root, no sign change to bracket): found by a run with another hash seed
# (hypothesis draws differently); such E0 are outside what the construction can promise (below)
@example(dict(mn=1.5, an=15.0, N1=32, N2=68, delta=3.0, g1=1.5, g2=1.5, b1=0.0, x1=0.0, dalpha=0.0, fallback_E=1.0))
@example(dict(mn=1.0, an=15.0, N1=12, N2=12, delta=3.0, g1=1.5, g2=1.5, b1=0.0, x1=0.0, dalpha=0.0, fallback_E=1.0))
def test_property_identities_and_round_trip(v):
    with np.errstate(all="ignore"):
        E0 = float(kernels.offset_residual(rad(v["an"] + v["dalpha"]), v["mn"], rad(v["an"]), v["N1"], v["N2"],
                                           rad(v["delta"]), v["x1"], rad(v["g1"]), rad(v["g2"]), rad(v["b1"]),
                                           0.0)[0])
    # an offset below 1e-4 mm is the round-off of intersecting axes (delta = gamma1 + gamma2 at alpha_n),
    # where Eq 17 touches E at a double root that no sign change brackets: treated as not constructible
    feasible = math.isfinite(E0) and E0 > 1e-4
    if not feasible:
        # alpha_nw0 is not admissible (no tangency there, or beta_w2 beyond 90 deg): whatever offset is
        # asked for, the design either succeeds with all identities or raises a proper DesignError.
        try:
            r = design(spec_from_dict(spec_dict(v, v["fallback_E"])))
        except DesignError as err:
            assert_good_error(err)
        else:
            assert check_identities(r) == []
        assume(False)
    try:
        r = design(spec_from_dict(spec_dict(v, E0)))
    except DesignError as err:
        # a solution exists by construction: only the physical checks may reject it
        assert_good_error(err)
        msg = str(err)
        assert "solves Eq 17" not in msg and "cannot touch" not in msg, msg
        assert "teeth" in msg or "helix" in msg, msg
        assume(False)
    assert abs(r.offset_residual_mm) <= max(1e-11, 8 * np.finfo(float).eps * E0)
    assert check_identities(r) == []
    assert_round_trip(r)


def test_vectorised_residual_matches_scalar():
    """The generated residual and its derivative agree with a central difference."""
    args = (6.0, rad(20), 29, 45, rad(13), 0.15, rad(2.0), rad(0.8), rad(23.0), 229.0)
    a = rad(22.0)
    h = 1e-6
    r0, dr = kernels.offset_residual(a, *args)
    rp, _ = kernels.offset_residual(a + h, *args)
    rm, _ = kernels.offset_residual(a - h, *args)
    assert float(dr) == pytest.approx((float(rp) - float(rm)) / (2 * h), rel=1e-6)


# ---------------------------------------------------------------------------
# Infeasible geometry
# ---------------------------------------------------------------------------

INFEASIBLE = [
    # (changes to case 1, key that must be named, direction word)
    (dict(pair__shaft_angle_deg=1.0, pinion__cone_angle_deg=8.0, gear__cone_angle_deg=8.0),
     "pair.shaft_angle_deg", "increase the shaft angle"),
    (dict(pair__offset_mm=5000.0), "pair.offset_mm", "reduce pair.offset_mm"),
    (dict(pinion__profile_shift=1.5, pinion__teeth=12), "pinion.profile_shift", "reduce pinion.profile_shift"),
    (dict(pair__offset_mm=300.0), "pair.offset_mm", "reduce pair.offset_mm"),  # gear x_t2 ~ 17: pointed
    (dict(pinion__profile_shift=-1.5, pinion__teeth=10), "pinion.profile_shift",
     "increase pinion.profile_shift"),  # tip circle inside the base circle
    (dict(pinion__helix_angle_deg=59.0, pair__shaft_angle_deg=3.0, pinion__cone_angle_deg=0.5,
          gear__cone_angle_deg=0.5), "pinion.profile_shift", "increase pair.offset_mm"),  # gear x_t2 ~ -4.5
    (dict(pinion__helix_angle_deg=-45.0, pair__shaft_angle_deg=30.0, pair__offset_mm=400.0),
     "pinion.helix_angle_deg", "increase pinion.helix_angle_deg"),  # |beta2| = 80.7 deg
    (dict(pinion__helix_angle_deg=-59.0, pair__shaft_angle_deg=44.0), "pinion.helix_angle_deg",
     "increase pinion.helix_angle_deg"),  # beta2 not real
    (dict(pinion__teeth=8, pinion__profile_shift=0.0), "pair.offset_mm", "reduce pair.offset_mm"),
    (dict(pinion__cone_angle_deg=15.0, pinion__helix_angle_deg=50.0, pair__normal_pressure_angle_deg=10.0,
          pair__shaft_angle_deg=45.0), "pinion.cone_angle_deg", "reduce |pinion.helix_angle_deg|"),  # alpha_PR < 0
    (dict(gear__cone_angle_deg=14.0, pair__normal_pressure_angle_deg=10.0, pair__shaft_angle_deg=40.0,
          pinion__helix_angle_deg=-20.0), "gear.cone_angle_deg", "increase pair.normal_pressure_angle_deg"),
]


@pytest.mark.parametrize("changes,key,direction", INFEASIBLE)
def test_infeasible_geometry_raises_design_error(changes, key, direction):
    with pytest.raises(DesignError) as info:
        design(spec_from_dict(modified(**changes)))
    err = info.value
    assert_good_error(err)
    msg = str(err)
    assert key in msg and key in err.keys, msg
    assert direction in msg, msg


@pytest.mark.parametrize("member", ["pinion", "gear"])
def test_zero_cone_angle_is_refused_by_the_spec_and_by_the_design(member):
    """The spec states the real range (non-zero); a DesignSpec built without the spec's check still
    gets the design's one-line error naming the key."""
    with pytest.raises(SpecError, match=rf"^{member}\.cone_angle_deg = 0\.0: must be a non-zero number from -15 to 15"):
        spec_from_dict(modified(**{f"{member}__cone_angle_deg": 0.0}))
    spec = spec_from_dict(modified())
    spec = dataclasses.replace(spec, **{member: dataclasses.replace(getattr(spec, member), cone_angle_deg=0.0)})
    with pytest.raises(DesignError) as info:
        design(spec)
    assert_good_error(info.value)
    assert f"increase |{member}.cone_angle_deg|" in str(info.value) and f"{member}.cone_angle_deg" in info.value.keys


def test_tangency_message_is_the_documented_one():
    with pytest.raises(DesignError, match=r"^pair\.shaft_angle_deg = 1\.0: the pitch cones cannot touch \(sin\^2 "
                                          r"delta < sin\^2 gw1 \+ sin\^2 gw2 \+ 2 sin gw1 sin gw2 cos delta"):
        design(spec_from_dict(modified(pair__shaft_angle_deg=1.0, pinion__cone_angle_deg=8.0,
                                       gear__cone_angle_deg=8.0)))


def test_offset_too_large_quotes_the_reachable_range():
    with pytest.raises(DesignError, match=r"offset is too large .* reduce pair\.offset_mm to at most 545\.7\d* mm"):
        design(spec_from_dict(modified(pair__offset_mm=5000.0)))


@pytest.mark.parametrize("offset", [1e-262, 1e-9])
def test_a_tiny_offset_is_too_small_not_too_large(offset):
    """E(alpha_nw) is 0 at the range's open end: an offset below the rest of the range is too small."""
    with pytest.raises(DesignError, match=r"offset is too small .* increase pair\.offset_mm to at least \d"):
        design(spec_from_dict(modified(pair__offset_mm=offset)))


def test_error_from_file_is_prefixed_with_the_path(tmp_path):
    text = (EXAMPLES / "case1.toml").read_text().replace("offset_mm = 229.0", "offset_mm = 5000.0")
    path = tmp_path / "far.toml"
    path.write_text(text)
    with pytest.raises(DesignError) as info:
        design(load_spec(path))
    assert str(info.value).startswith(f"{path}: pair.offset_mm = 5000.0: ")
    assert info.value.detail.startswith("pair.offset_mm = 5000.0: ")


def test_undercut_is_a_note_not_an_error():
    # 12 teeth, x_t = -0.3 and the offset for alpha_nw = alpha_n: undercut, but P stays on the active profile
    # (pinion x_t = -1.2 on case 1, used before, puts P above the pinion tip: now rejected, see below)
    r = design(spec_from_dict(modified(pinion__teeth=12, pinion__profile_shift=-0.3, pair__offset_mm=172.193)))
    assert any(n.startswith("undercut: pinion left flank") for n in r.notes)
    assert all("increase pinion.profile_shift" in n for n in r.notes)
    assert check_identities(r) == []
    assert "note: undercut: pinion" in format_table1(r)


def test_several_roots_choose_the_one_closest_to_alpha_n():
    """Opposite-hand cone angles: Eq 17 also has a root at a tiny alpha_nw; the note says which was taken."""
    r = design(spec_from_dict(modified(gear__cone_angle_deg=-2.0)))
    assert deg(r.working_normal_pressure_angle) == pytest.approx(18.3375, abs=1e-4)
    assert len(r.notes) == 1 and r.notes[0].startswith("Eq 17 has 2 roots alpha_nw = 0.88")
    assert "chose 18.3375 deg, the one closest to alpha_n = 20 deg" in r.notes[0]
    assert check_identities(r) == []


def test_steep_end_of_the_tangency_range_is_solved_to_float_resolution(monkeypatch):
    """E = 0.125 mm for gears of ~1500 mm: E(alpha_nw) ~ sqrt(alpha_nw - end), so |residual| 1e-11 is out of
    reach; the design accepts alpha_nw at floating-point resolution and says so in a note.

    The pair itself is infeasible (alpha_nw = 8.4 deg puts P below the pinion's form circle); the root
    finder is tested with that last check switched off."""
    d = {"pair": {"normal_module_mm": 15.962225365159304, "normal_pressure_angle_deg": 18.66216912201765,
                  "shaft_angle_deg": 61.565709030041525, "offset_mm": 0.12530196727260706},
         "pinion": {"teeth": 101, "cone_angle_deg": -14.886566134330275, "helix_angle_deg": 8.373929582436759,
                    "profile_shift": 0.11894893418084784, "face_width_mm": 50.0},
         "gear": {"teeth": 287, "cone_angle_deg": -12.110536505916276, "face_width_mm": 50.0}}
    with pytest.raises(DesignError, match=r"pitch point P .* below the start of the active profile"):
        design(spec_from_dict(d))
    monkeypatch.setattr("beveloid.design.checks.check_pitch_point", lambda *args: None)
    r = design(spec_from_dict(d))
    assert any(n.startswith("Eq 17 solved only to |E(alpha_nw) - E| = ") for n in r.notes)
    assert abs(r.offset_residual_mm) < 1e-7
    assert check_identities(r) == []
    assert_round_trip(r)


def test_negative_cone_angles_satisfy_the_identities():
    for changes in (dict(pinion__cone_angle_deg=-2.0), dict(pinion__cone_angle_deg=-2.0, gear__cone_angle_deg=-0.8)):
        r = design(spec_from_dict(modified(**changes)))
        assert check_identities(r) == []
        assert_round_trip(r)


@pytest.mark.parametrize("args,name", [
    ((rad(21), rad(80), rad(0.75), rad(23)), "pinion_working_cone_angle"),  # Eq 25: |sin gamma1| > 1
    ((rad(21), rad(12), rad(12), rad(23)), "pair.shaft_angle_deg"),  # no tangency
    ((rad(21), 0.0, rad(0.75), rad(23)), "pinion_working_cone_angle"),
    ((rad(95), rad(1.9), rad(0.75), rad(23)), "alpha_nw"),
    ((rad(21), rad(1.9), rad(0.75), math.nan), "pinion_working_helix_angle"),
])
def test_indirect_infeasible(args, name):
    with pytest.raises(DesignError) as info:
        indirect_design(load_spec(EXAMPLES / "case1.toml"), *args)
    assert name in str(info.value) and name in info.value.keys
    assert "\n" not in str(info.value)


def test_design_needs_a_spec():
    with pytest.raises(TypeError):
        design(base_dict())  # type: ignore[arg-type]


# ---------------------------------------------------------------------------
# Reports and CLI
# ---------------------------------------------------------------------------

CONTRACT_TOP = ("working_normal_pressure_angle_deg", "fpd_angle_left_deg", "fpd_angle_right_deg")
CONTRACT_MEMBER = ("helix_angle_deg", "profile_shift", "transverse_angular_factor", "mounting_distance_mm",
                   "working_cone_angle_deg", "working_helix_angle_deg", "working_pitch_radius_mm",
                   "reference_pitch_radius_mm")


def test_json_contract(case1):
    j = design_json(case1)
    assert j == case1.to_json_dict()
    for key in CONTRACT_TOP:
        assert type(j[key]) is float
    assert j["working_normal_pressure_angle_deg"] == deg(case1.working_normal_pressure_angle)
    assert j["fpd_angle_left_deg"] == pytest.approx(7.570207, abs=1e-6)
    assert j["fpd_angle_right_deg"] == pytest.approx(2.408103, abs=1e-6)
    for name in ("pinion", "gear"):
        m = case1.member(name)
        for key in CONTRACT_MEMBER:
            assert type(j[name][key]) is float, key
        assert j[name]["helix_angle_deg"] == deg(m.helix_angle)
        assert j[name]["working_cone_angle_deg"] == deg(m.working_cone_angle)
        assert j[name]["working_helix_angle_deg"] == deg(m.working_helix_angle)
        assert j[name]["mounting_distance_mm"] == m.mounting_distance_mm
        assert j[name]["working_pitch_radius_mm"] == m.working_pitch_radius_mm
        assert j[name]["reference_pitch_radius_mm"] == m.reference_pitch_radius_mm
        assert j[name]["teeth"] == m.teeth and type(j[name]["teeth"]) is int
        assert j[name]["cone_angle_deg"] == pytest.approx(deg(m.cone_angle))
        assert type(j[name]["working_mounting_distance_mm"]) is float
    assert j["pinion"]["helix_angle_deg"] == pytest.approx(23.0)
    assert j["gear"]["profile_shift"] == pytest.approx(0.192725, abs=1e-6)
    assert j["notes"] == []
    assert json.loads(json.dumps(j, allow_nan=False)) == j


def test_table_has_the_table1_rows(case1):
    text = format_table1(case1)
    for label in ("Normal module (mm)", "Normal pressure angle (deg)", "Number of teeth", "Shaft angle (deg)",
                  "Offset (mm)", "Cone angle (deg)", "Helix angle (deg)", "Profile shifting factor",
                  "Total face-width (mm)", "Transverse angular factor", "Mounting distance (mm)",
                  "Working cone angle (deg)", "Working helix angle (deg)", "FPD-angle (deg)",
                  "Working normal pressure angle (deg)"):
        assert label in text
    for _label, symbol in TABLE1_ROWS:
        assert f"| {symbol} " in text
    assert "Symbol" in text and "Pinion" in text and "Gear" in text
    assert "23.000000 (RH)" in text and "-10.382154 (LH)" in text
    assert "2687.713989" in text and "10297.010200" in text and "0.192725" in text
    assert "21.249621" in text and "7.570207" in text and "2.408103" in text


def _cli(argv):
    parser = argparse.ArgumentParser()
    cli_design.configure(parser)
    return cli_design.run(parser.parse_args(argv))


def test_cli_design_table_and_json(capsys):
    assert _cli([str(EXAMPLES / "case2.toml")]) == 0
    out = capsys.readouterr().out
    assert "Working cone angle (deg)" in out and "0.749642" in out
    assert _cli([str(EXAMPLES / "case2.toml"), "--json"]) == 0
    j = json.loads(capsys.readouterr().out)
    assert j["gear"]["mounting_distance_mm"] == pytest.approx(10368.35, abs=0.01)


def test_cli_design_errors_are_raised_for_the_main_cli(tmp_path):
    with pytest.raises(SpecError):
        _cli([str(tmp_path / "missing.toml")])
    path = tmp_path / "bad.toml"
    path.write_text((EXAMPLES / "case1.toml").read_text().replace("offset_mm = 229.0", "offset_mm = 5000.0"))
    with pytest.raises(DesignError):
        _cli([str(path)])


def test_runtime_does_not_import_sympy(tmp_path):
    import subprocess
    import sys

    code = ("import sys, beveloid.design, beveloid.design.report, beveloid.cli.design;"
            "from beveloid.spec import load_spec; beveloid.design.design(load_spec(sys.argv[1]));"
            "print('sympy' in sys.modules)")
    # run outside the checkout: there `python -c` would import the bare beveloid/ folder
    out = subprocess.run([sys.executable, "-c", code, str(EXAMPLES / "case1.toml")], capture_output=True,
                         text=True, check=True, cwd=tmp_path)
    assert out.stdout.strip() == "False"

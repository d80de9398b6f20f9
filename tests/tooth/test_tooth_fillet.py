"""The root fillet (derivations/root_fillet.py, generated/root_fillet.py, beveloid/tooth/fillet.py):
the envelope condition at 50 digits, Jacobians by complex step, the rho_a0 -> 0 limit (the
trochoid of the tip edge) and the continuous junction with the flank (point and tangent plane)."""
from __future__ import annotations

import math
import random
import tomllib

import mpmath
import numpy as np
import pytest
import sympy as sp

from beveloid.derivations import crowned_flank as cf
from beveloid.derivations import eq04_07_tooth_surface as involute
from beveloid.derivations import root_fillet as rf
from beveloid.derivations.eq01_03_rack_cutter import LEFT, RIGHT, rack_point
from beveloid.derivations.symbols import a, alpha_n, b, beta, gamma, l, m_n, phi, r, s, u
from beveloid.generated import root_fillet
from beveloid.pair import Pair
from beveloid.spec import SpecError, example_text, spec_from_dict
from beveloid.tooth import fillet as F

SIGMAS = (LEFT, RIGHT)
FLANKS = ("left", "right")


def _domain(rng):
    def uni(lo, hi):
        return mpmath.mpf(lo) + (mpmath.mpf(hi) - mpmath.mpf(lo)) * mpmath.mpf(rng.random())
    mn = uni(2, 8)
    return {rf.psi: uni(0, 1.2), u: uni(-30, 30), alpha_n: uni(0.25, 0.45), beta: uni(-0.6, 0.6),
            gamma: uni(-0.12, 0.12), a: mn * uni(1.0, 1.4), b: mn * mpmath.pi / 4, s: uni(-3, 3), r: uni(15, 400),
            m_n: mn, rf.rho: mn * uni(0, 0.4), cf.W: uni(10, 120), cf.C_alpha: uni(0, 200), cf.C_beta: uni(0, 200)}


def _max_abs(exprs, n=8, seed=7):
    rng = random.Random(seed)
    exprs = list(exprs)
    syms = sorted(set().union(*[e.free_symbols for e in exprs]), key=str)
    f = sp.lambdify(syms, exprs, modules="mpmath")
    worst = mpmath.mpf(0)
    with mpmath.workdps(50):
        for _ in range(n):
            point = _domain(rng)
            worst = max(worst, max(abs(v) for v in f(*[point[k] for k in syms])))
    return float(worst)


def _spec(**members):
    d = tomllib.loads(example_text("case1"))
    for name, keys in members.items():
        d[name].update(keys)
    return d


@pytest.fixture(scope="module")
def rounded():
    """Case 1 with ISO 53 profile A tip rounds, the pinion crowned (so the round moves with the rack)."""
    return Pair.from_spec(_spec(pinion=dict(cutter_tip_radius_coefficient=0.38, profile_crowning_um=20.0,
                                            lead_crowning_um=15.0),
                                gear=dict(cutter_tip_radius_coefficient=0.25)))


# ---------------------------------------------------------------------------------------------
# the derivation, at 50 digits
# ---------------------------------------------------------------------------------------------

@pytest.mark.parametrize("sigma", SIGMAS)
def test_round_is_tangent_to_the_tip_line_and_the_edge(sigma):
    """Without crowning: the round touches the tip line x_n = -a + s at psi = 0 with normal (1, 0),
    and meets the straight edge at l_t with the edge's normal; its centre is rho from both."""
    centre, q, n = (e.xreplace({cf.C_alpha: 0}) for e in rf.round_normal_section(sigma))
    edge = rack_point(sigma).xreplace({gamma: 0, beta: 0, u: 0})  # the normal section itself
    psi_j = rf.junction_psi().xreplace({cf.C_alpha: 0})
    at_j = (q - edge.xreplace({l: rf.junction_l()})).xreplace({rf.psi: psi_j})
    assert _max_abs(list(at_j) + [q[0].xreplace({rf.psi: 0}) - (-a + s), centre[0] - (-a + s) - rf.rho,
                                  (n.xreplace({rf.psi: psi_j}) - rf.edge_normal(sigma)).norm()]) < 1e-45


def test_largest_round_meets_the_rack_tooth_centre_line():
    """At rho_max the round's point on the tip line lies on the rack tooth's centre line sigma Y = -pi m_n / 2."""
    for sigma in SIGMAS:
        q = rf.round_normal_section(sigma)[1].xreplace({cf.C_alpha: 0})
        y_tip = q[1].xreplace({rf.psi: 0, rf.rho: rf.max_radius()})
        assert _max_abs([sigma * y_tip + sp.pi * m_n / 2]) < 1e-45


@pytest.mark.parametrize("sigma", SIGMAS)
def test_eq7_is_the_envelope_condition_of_the_round(sigma):
    """n . dR/dphi = 0 on the family of translated rounds at phi(psi, u); the normal is the round's
    (orthogonal to both of its tangents) and of unit length."""
    pc = rf.round_point(sigma)
    nc = rf.round_normal(sigma)
    family = involute.generated_family(pc)
    point, normal, phi_pu = rf.fillet_surface(sigma)
    condition = (involute.M_ic[:3, :3] * nc).dot(family.diff(phi)).xreplace({phi: phi_pu})
    checks = [condition, nc.dot(pc.diff(rf.psi)), nc.dot(pc.diff(u)), nc.dot(nc) - 1]
    checks += list(point - family.xreplace({phi: phi_pu}))
    assert _max_abs(checks) < 1e-40


@pytest.mark.parametrize("sigma", SIGMAS)
def test_sharp_rack_limit_is_the_trochoid_of_the_tip_edge(sigma):
    """rho_a0 = 0 (no crowning): the fillet point is the rack's tip edge (l = 0) carried by the
    generating motion to the fillet's roll angle, i.e. the surface the tip edge sweeps."""
    point, _, phi_pu = rf.fillet_surface(sigma)
    flat = {rf.rho: 0, cf.C_alpha: 0, cf.C_beta: 0}
    swept = involute.generated_family(rack_point(sigma).xreplace({l: 0}))
    diff = (point.xreplace(flat) - swept.xreplace({phi: phi_pu.xreplace(flat)}))
    assert _max_abs(list(diff)) < 1e-40


# ---------------------------------------------------------------------------------------------
# the generated kernels on designed members
# ---------------------------------------------------------------------------------------------

def _grid(tr, geometry, member):
    w = geometry.member(member).face_width_mm
    psi = np.linspace(0.0, float(tr.junction_psi), 5)[:, None]
    return psi, np.linspace(-0.4 * w, 0.4 * w, 4)[None, :]


@pytest.mark.parametrize("flank", FLANKS)
@pytest.mark.parametrize("member", ("pinion", "gear"))
def test_jacobians_by_complex_step(rounded, flank, member):
    g = rounded.geometry
    tr = F.tip_round(g, member)
    psi, uu = _grid(tr, g, member)
    psi, uu = np.broadcast_arrays(psi, uu)
    jet = F.fillet_jet(g, member, flank, psi, uu)
    h = 1e-30
    for k, (dp, du) in enumerate(((h, 0), (0, h))):
        f = F.fillet(g, member, flank, psi + 1j * dp, uu + 1j * du)
        np.testing.assert_allclose(f.point.imag / h, jet.point_D_pu[..., k], rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(f.normal.imag / h, jet.normal_D_pu[..., k], rtol=1e-12, atol=1e-12)
    # and the normal is the surface's: orthogonal to both tangents
    ortho = np.einsum("...i,...ik->...k", jet.normal, jet.point_D_pu)
    assert np.max(np.abs(ortho)) < 1e-12


@pytest.mark.parametrize("flank", FLANKS)
@pytest.mark.parametrize("member", ("pinion", "gear"))
def test_junction_with_the_flank_is_continuous(rounded, flank, member):
    """At psi_J the fillet meets the flank point of l_t: same point, same tangent plane
    (the flank's normal is orthogonal to the fillet's tangents), also for the crowned pinion."""
    g = rounded.geometry
    tr = F.tip_round(g, member)
    uu = np.linspace(-10.0, 10.0, 5)
    jet = F.fillet_jet(g, member, flank, float(tr.junction_psi), uu)
    flank_pt = g.surface_jet(member, flank, float(tr.junction_l), uu)
    np.testing.assert_allclose(jet.point, flank_pt.point, atol=1e-10)
    np.testing.assert_allclose(jet.normal, flank_pt.normal, atol=1e-12)
    assert np.max(np.abs(np.einsum("...i,...ik->...k", flank_pt.normal, jet.point_D_pu))) < 1e-10
    # the round's junction is the flank's new form point: l_t = rho (1 - sin alpha_n) / cos alpha_n
    a_n = g.normal_pressure_angle
    rho = g.member(member).cutter_tip_radius_mm
    assert rho > 0 and float(tr.junction_l) == pytest.approx(rho * (1 - math.sin(a_n)) / math.cos(a_n), rel=1e-14)


@pytest.mark.parametrize("flank", FLANKS)
def test_deepest_fillet_point_lies_on_the_root_cone(rounded, flank):
    """psi = 0 cuts the root: radius r + (s - a)/cos(gamma) + z tan(gamma) (the rack's tip line, uncrowned gear)."""
    g = rounded.geometry
    m = g.gear
    pt = F.fillet(g, "gear", flank, 0.0, np.linspace(-8, 8, 5)).point
    root = m.pitch_radius_mm + (m.rack_shift_mm - m.cutter_addendum_mm) / math.cos(m.cone_angle) \
        + pt[:, 2] * math.tan(m.cone_angle)
    np.testing.assert_allclose(np.hypot(pt[:, 0], pt[:, 1]), root, atol=1e-10)


def test_small_round_tends_to_the_sharp_rack(pair1):
    """rho_a0 -> 0: the fillet converges (linearly in rho) to the trochoid of the sharp rack."""
    g0 = pair1.geometry
    psi = np.linspace(0.0, float(F.tip_round(g0, "pinion").junction_psi), 7)
    sharp = F.fillet(g0, "pinion", "left", psi, 2.0).point
    gaps = []
    for coef in (1e-3, 1e-5):
        g = Pair.from_spec(_spec(pinion=dict(cutter_tip_radius_coefficient=coef))).geometry
        gaps.append(np.max(np.abs(F.fillet(g, "pinion", "left", psi, 2.0).point - sharp)))
    assert gaps[1] < 1e-4 * 3 and gaps[1] < gaps[0] / 50


def test_tip_round_key_is_checked_against_the_largest_round():
    top = root_fillet.tip_round(F.fillet_params(Pair.example("case1").geometry, "pinion")).max_radius
    m_n = Pair.example("case1").geometry.normal_module_mm
    a_n = math.radians(20.0)
    expected = (math.pi / 4 - 1.25 * math.tan(a_n)) * math.cos(a_n) / (1 - math.sin(a_n))
    assert float(top) / m_n == pytest.approx(expected, rel=1e-14)
    spec_from_dict(_spec(gear=dict(cutter_tip_radius_coefficient=expected * 0.999)))
    with pytest.raises(SpecError) as err:
        spec_from_dict(_spec(gear=dict(cutter_tip_radius_coefficient=expected * 1.001)))
    msg = str(err.value)
    assert "\n" not in msg and "gear.cutter_tip_radius_coefficient" in msg and "at most 0.4719" in msg
    with pytest.raises(SpecError, match="pinion.cutter_tip_radius_coefficient"):
        spec_from_dict(_spec(pinion=dict(cutter_tip_radius_coefficient=-0.1)))


def test_blank_starts_the_flank_at_the_rounds_junction(rounded, pair1):
    """The TCA blank's form-limit margin is l - l_t (generated flank_boundaries); 0 on the sharp rack."""
    from beveloid.generated import flank_boundaries

    for member in ("pinion", "gear"):
        g = rounded.geometry
        l_t = float(F.tip_round(g, member).junction_l)
        assert g.member(member).form_limit_l_mm == l_t > 0
        assert pair1.geometry.member(member).form_limit_l_mm == 0.0
        l = np.linspace(0.0, 3.0, 7)
        point = np.array([g.member(member).pitch_radius_mm, 0.0, 0.0])
        form = flank_boundaries.BOUNDARIES.index("form limit")
        margins = flank_boundaries.flank_margins(point, l, g.member(member).blank()).margins[..., form]
        np.testing.assert_array_equal(margins, l - l_t)
        sharp = flank_boundaries.flank_margins(point, l, pair1.geometry.member(member).blank()).margins[..., form]
        np.testing.assert_array_equal(sharp, l)

"""The contact kinematics on a crossed pair: the sliding velocity of every loaded cell is the
difference of the members' velocities omega x r about their axes, projected on the tangent plane
(built here from the rotation axes alone), and the crossed-helical efficiency bound."""
import math

import numpy as np
import pytest

from beveloid import ltca, tribology
from beveloid.generated import placement
from beveloid.pair import Pair



@pytest.fixture(scope="module")
def case1(cases):
    pair = Pair.example("case1")
    return pair, ltca.analyze(pair, ltca.LoadCase(100.0), cases.plate_options(positions=5))


def test_sliding_velocity_is_the_difference_of_omega_cross_r(case1):
    pair, res = case1
    geom = pair.geometry
    cells = tribology.build(res, geom, pair.errors, ltca.Material().e_star_mpa)
    n1, n2 = geom.pinion.teeth, geom.gear.teeth
    w1 = 1.0  # rad/s: the cells hold velocities per rad/s
    pl = geom.placement()
    pin = placement.pinion_placement(0.0, pl)
    gear = placement.gear_placement(0.0, np.asarray(pair.errors, float), pl)
    axis1, c1 = pin.rotation[:, 2], pin.translation  # the pinion turns about z_f through its origin
    axis2, c2 = gear.rotation[:, 2], gear.translation  # the gear about its own z through its origin
    assert np.allclose(axis1, [0, 0, 1])
    checked = 0
    for j, k, i in zip(*np.nonzero(cells.loaded)):
        phi = res.pair_pinion_angle[j, k]
        rz = np.array([[math.cos(phi), -math.sin(phi), 0], [math.sin(phi), math.cos(phi), 0], [0, 0, 1]])
        r = rz @ res.gap.pinion_point[j, k, i] + c1  # the cell's pinion point in S_f
        lu = res.gap.pinion_lu[j, k, i]
        n = rz @ geom.surface("pinion", res.flank, lu[0], lu[1]).normal
        v1 = np.cross(w1 * axis1, r - c1) * 1e-3
        v2 = np.cross(-w1 * n1 / n2 * axis2, r - c2) * 1e-3
        dv = v1 - v2
        expected = dv - dv.dot(n) * n
        got = cells.sliding_velocity[j, k, i]
        assert np.linalg.norm(got - expected) <= 1e-9 * np.linalg.norm(expected)
        checked += 1
    assert checked > 100


@pytest.mark.parametrize("shaft_deg", [10.0, 20.0])
def test_crossed_helical_efficiency_below_the_bound(shaft_deg, cases):
    mu = 0.05
    pair = cases.crossed_helical(shaft_deg, mu)
    tri = tribology.evaluate(ltca.analyze(pair, ltca.LoadCase(200.0), cases.plate_options()), pair, 1500.0)
    phi, s = math.atan(mu), math.radians(shaft_deg)
    assert tri.efficiency < (math.cos(s + phi) + 1) / (math.cos(s - phi) + 1)


def test_crossed_efficiency_approaches_the_parallel_axis_value(cases):
    effs = {}
    for shaft in (0.0001, 1.0, 5.0, 10.0):
        pair = cases.crossed_helical(shaft, 0.05)
        effs[shaft] = tribology.evaluate(ltca.analyze(pair, ltca.LoadCase(200.0), cases.plate_options()), pair, 1500.0).efficiency
    gaps = [abs(effs[s] - effs[0.0001]) for s in (10.0, 5.0, 1.0)]
    assert gaps[0] > gaps[1] > gaps[2]
    assert gaps[2] < 0.1 * gaps[0]


@pytest.mark.slow  # sympy's simplification, a few seconds: the numeric test above holds the same fields
def test_derived_velocities_are_rigid_body_fields():
    """The model behind generated/contact_kinematics.py: both velocity fields equal omega x (R - c) about each
    member's axis, symbolically (derivations/contact_kinematics.py)."""
    from beveloid.derivations import contact_kinematics

    for residual in contact_kinematics.velocity_field_residual():
        assert all(e == 0 for e in residual)

"""The symbolic models reproduce every equation of the paper; the page documenting them is current.

The 50-digit check of all equations runs once per session (fixture ``verification`` in
conftest.py).  The property tests below hold the models to geometric facts that the
equation-by-equation comparison does not cover.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from beveloid.derivations import eq01_03_rack_cutter as rack
from beveloid.derivations import eq04_07_tooth_surface as surface
from beveloid.derivations.docs import REGENERATE_HINT, check_derivations_md
from beveloid.derivations.symbols import a, alpha_n, b, beta, gamma, l, r, s, u

REPO = Path(__file__).resolve().parents[2]

DEFINITIONS = {8, 10, 11, 15, 21, 28, 29, 36, 37}
ALL = range(1, 39)
FLANKS = pytest.mark.parametrize("sigma", [rack.LEFT, rack.RIGHT], ids=["left", "right"])


@pytest.fixture(scope="module")
def by_number(verification):
    eqs, results = verification
    return {r.equation: (e, r) for e, r in zip(eqs, results)}


# ---------------------------------------------------------------------------------------
# Every equation: verified (or a definition)
# ---------------------------------------------------------------------------------------


@pytest.mark.parametrize("number", ALL)
def test_equation(number, by_number):
    _eq, res = by_number[number]
    detail = f"Eq {number} ({res.title}): {res.status}, {res.method}, max rel diff {res.max_rel_diff}. {res.note}"
    assert res.status in {"verified", "definition"}, detail
    expected = "definition" if number in DEFINITIONS else "verified"
    assert res.status == expected, detail
    if res.status == "verified":
        assert res.max_rel_diff is not None and res.max_rel_diff < 1e-40, detail


def test_exactly_these_are_definitions(verification):
    _eqs, results = verification
    assert {r.equation for r in results if r.status == "definition"} == DEFINITIONS


def test_each_equation_once(verification):
    eqs, results = verification
    assert [e.number for e in eqs] == list(ALL)
    assert [r.equation for r in results] == list(ALL)


# ---------------------------------------------------------------------------------------
# Geometric properties, at random points (float64)
# ---------------------------------------------------------------------------------------

RNG_SEED = 2013
N_POINTS = 60


def _random_points(rng, n, with_shift):
    """Realistic cutter/gear data: m_n = 6 mm, a = 1.25 m_n, b near pi m_n / 4."""
    deg = np.pi / 180
    for _ in range(n):
        yield {
            l: rng.uniform(0.0, 2.25 * 6 / np.cos(25 * deg)),
            u: rng.uniform(-30.0, 30.0),
            alpha_n: rng.uniform(15, 25) * deg,
            beta: rng.uniform(-35, 35) * deg,
            gamma: rng.uniform(-6, 6) * deg,
            a: 1.25 * 6 * rng.uniform(0.9, 1.1),
            b: np.pi * 6 / 4 * rng.uniform(0.9, 1.1),
            s: rng.uniform(-3.0, 3.0) if with_shift else 0.0,
            r: rng.uniform(40.0, 300.0),
        }


def _numeric(exprs, syms):
    f = sp.lambdify(syms, [list(e) for e in exprs], modules="numpy")
    return lambda point: [np.array(v, dtype=float) for v in f(*[point[x] for x in syms])]


@FLANKS
def test_rack_normal_is_signed_unit_cross_product(sigma):
    """rack_normal(sigma) == sigma * (dR/dl x dR/du), and it has unit length."""
    R = rack.rack_point(sigma)
    cross = R.diff(l).cross(R.diff(u))
    syms = [l, u, alpha_n, beta, gamma, a, b, s]
    evaluate = _numeric([rack.rack_normal(sigma), cross], syms)
    for point in _random_points(np.random.default_rng(RNG_SEED), N_POINTS, with_shift=True):
        n, c = evaluate(point)
        np.testing.assert_allclose(n, sigma * c, rtol=0, atol=1e-12)
        assert abs(np.linalg.norm(n) - 1) < 1e-12


@FLANKS
def test_tooth_surface_normal_is_surface_normal(sigma):
    """Envelope: the carried-over cutter normal is normal to the generated surface (with rack shift s != 0)."""
    point, normal, _phi = surface.tooth_surface(sigma)
    cross = point.diff(l).cross(point.diff(u))
    syms = [l, u, alpha_n, beta, gamma, a, b, s, r]
    evaluate = _numeric([normal, cross], syms)
    orientation = set()
    for p in _random_points(np.random.default_rng(RNG_SEED + 1), N_POINTS, with_shift=True):
        n, c = evaluate(p)
        assert abs(np.linalg.norm(n) - 1) < 1e-12
        parallel_defect = np.linalg.norm(np.cross(n, c)) / (np.linalg.norm(n) * np.linalg.norm(c))
        assert parallel_defect < 1e-9, f"normal not parallel to dP/dl x dP/du at {p}: {parallel_defect:.2e}"
        orientation.add(bool(np.dot(n, c) > 0))
    assert len(orientation) == 1, "the surface normal flips orientation across the flank"


# ---------------------------------------------------------------------------------------
# docs/derivations.md is generated from the models and must be current
# ---------------------------------------------------------------------------------------


def test_derivations_md_is_current(verification):
    ok, diff = check_derivations_md(REPO / "docs" / "derivations.md", results=verification)
    if not ok:
        lines = diff.splitlines()
        shown = "\n".join(lines[:200]) + (f"\n... ({len(lines) - 200} more diff lines)" if len(lines) > 200 else "")
        pytest.fail(f"docs/derivations.md is stale: {REGENERATE_HINT}\n{shown}", pytrace=False)

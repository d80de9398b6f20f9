"""derivations/tooth_plate_coupling.py: the cantilever plate strip solved, its printed forms, and the
generated kernels against an independent 50-digit evaluation."""
from __future__ import annotations

import mpmath as mp
import numpy as np
import pytest
import sympy as sp

from beveloid.derivations import tooth_plate_coupling as model
from beveloid.generated import tooth_plate_coupling as generated


@pytest.fixture(scope="module")
def solved():
    return model.strip_deflection(), model.solved_ratio()


def _is_zero(expr):
    """expr (a rational function of x, k, h, ... and sinh / cosh of k x and h k) is identically zero: its
    numerator, the hyperbolic functions as symbols, reduces to 0 modulo cosh^2 - sinh^2 = 1 of both arguments
    (the two relations' leading terms are coprime: a Groebner basis, the remainder is 0 exactly on the ideal).
    The same verdict as sp.simplify(expr) == 0 in a quarter of its time."""
    k, h, x = model.k, model.h, model.x
    S, C, s, c = sp.symbols("S C s c")
    poly = expr.subs({sp.sinh(h * k): S, sp.cosh(h * k): C, sp.sinh(k * x): s, sp.cosh(k * x): c})
    assert not poly.has(sp.sinh, sp.cosh), poly
    numerator, _ = sp.fraction(sp.cancel(sp.together(poly)))
    return sp.reduced(sp.expand(numerator), [C**2 - S**2 - 1, c**2 - s**2 - 1], S, C, s, c)[1] == 0


def test_solution_satisfies_the_plate_equation_and_the_edges(solved):
    f, _ = solved
    x, k, h, nu, q, D = model.x, model.k, model.h, model.nu, model.q, model.D
    assert _is_zero(model.plate_equation_residual(f))
    assert _is_zero(f.subs(x, 0)) and _is_zero(sp.diff(f, x).subs(x, 0))
    assert _is_zero((sp.diff(f, x, 2) - nu * k**2 * f).subs(x, h))
    assert _is_zero((-D * (sp.diff(f, x, 3) - (2 - nu) * k**2 * sp.diff(f, x))).subs(x, h) - q)
    # and it says no where an edge condition does not hold (the load at the free edge off by a part)
    assert not _is_zero((-D * (sp.diff(f, x, 3) - (2 - nu) * k**2 * sp.diff(f, x))).subs(x, h) - q * (1 + nu / 100))


def test_printed_forms_equal_the_solved_ratio_in_50_digits(solved):
    _, ratio = solved
    t, nu = model.t, model.nu
    rng = np.random.default_rng(7)
    for tv, nv in zip(rng.uniform(0.05, 12.0, 12), rng.uniform(0.2, 0.4, 12)):
        at = {t: sp.Float(tv, 60), nu: sp.Float(nv, 60)}
        exact = sp.N(ratio.subs(at), 50)
        for form in (model.printed_ratio(), model.edge_compliance_ratio()):
            assert abs(sp.N(form.subs(at), 50) / exact - 1) < 1e-40


def test_limits():
    t, nu = model.t, model.nu
    series = model.edge_compliance_ratio_series()
    assert series.subs(t, 0) == 1
    assert sp.simplify(series.coeff(t, 2) - (nu - sp.Rational(4, 5))) == 0  # the string's lambda^2 / h^2
    assert all(series.coeff(t, n) == 0 for n in (1, 3, 5, 7))  # R is even in t
    assert sp.simplify(model.large_t_limit() - 6 / ((1 - nu) * (3 + nu))) == 0


def test_generated_kernels_against_mpmath():
    """Closed form for t >= 0.03 and series below it, each within 1e-12 of the printed form in 50 digits."""
    mp.mp.dps = 50

    def printed(t, nu):
        t, nu = mp.mpf(t), mp.mpf(nu)
        return 3 * (mp.sinh(2 * t) - 2 * t) / (t**3 * ((1 - nu) * (3 + nu) * mp.sinh(t) ** 2 + (1 - nu) ** 2 * t**2 + 4))

    for t in np.concatenate([np.geomspace(0.03, 400.0, 40), [0.03]]):
        for nu in (0.25, 0.3, 0.35):
            ref = float(printed(t, nu))
            assert generated.edge_compliance_ratio(t, nu).ratio == pytest.approx(ref, rel=1e-12)
    for t in np.geomspace(1e-6, 0.03, 20):
        ref = float(printed(t, 0.3))
        assert generated.edge_compliance_ratio_series(t, 0.3).ratio == pytest.approx(ref, rel=1e-13)

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


def test_solution_satisfies_the_plate_equation_and_the_edges(solved):
    f, _ = solved
    x, k, h, nu, q, D = model.x, model.k, model.h, model.nu, model.q, model.D
    assert sp.simplify(model.plate_equation_residual(f)) == 0
    assert sp.simplify(f.subs(x, 0)) == 0 and sp.simplify(sp.diff(f, x).subs(x, 0)) == 0
    assert sp.simplify((sp.diff(f, x, 2) - nu * k**2 * f).subs(x, h)) == 0
    assert sp.simplify((-D * (sp.diff(f, x, 3) - (2 - nu) * k**2 * sp.diff(f, x))).subs(x, h) - q) == 0


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

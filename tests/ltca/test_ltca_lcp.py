"""beveloid.ltca.mechanics.lcp: the half-space contact converges to Hertz, equilibrium, complementarity.

Complementarity is checked here from C, h and the returned numbers, not from the solver's
own residuals; the small problem is also solved by scipy's SLSQP as an independent oracle.
"""
from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg
from scipy.optimize import minimize

from beveloid.ltca.mechanics.halfspace import reduced_modulus_mpa, tensor_grid, tensor_influence_matrix_mm_per_mpa
from beveloid.ltca.mechanics.hertz import hertz_point_contact
from beveloid.ltca.mechanics.lcp import CellWeights, SolveLimits, prepare_compliance, solve_contact

E_STAR = reduced_modulus_mpa()
RX_MM, RY_MM, LOAD_N = 20.0, 60.0, 1000.0
HERTZ = hertz_point_contact(1 / (2 * RX_MM), 1 / (2 * RY_MM), LOAD_N, E_STAR)


def hertz_problem(n: int, margin: float = 1.25):
    """Odd n x n uniform grid over margin x the Hertz ellipse (a cell centred on the origin)."""
    ax, ay = margin * HERTZ.semi_axis_x_mm, margin * HERTZ.semi_axis_y_mm
    xe, ye = np.linspace(-ax, ax, n + 1), np.linspace(-ay, ay, n + 1)
    cells = tensor_grid(xe, ye)
    c = tensor_influence_matrix_mm_per_mpa(xe, ye, E_STAR)
    h = cells.x_mm**2 / (2 * RX_MM) + cells.y_mm**2 / (2 * RY_MM)
    return cells, c, h


def semi_axes_from_moments(cells, p):
    """a = sqrt(5 <x^2>) under the load: exact for the Hertz (ellipsoidal) pressure."""
    f = cells.area_mm2 * p
    return np.sqrt(5 * (f @ cells.x_mm**2) / f.sum()), np.sqrt(5 * (f @ cells.y_mm**2) / f.sum())


def assert_complementary(c, h, w, sol, tol=1e-9):
    p = sol.pressure_mpa
    g = h - sol.approach_mm * w + c @ p
    scale = np.abs(c @ p).max()
    assert p.min() >= 0.0
    assert g.min() >= -tol * scale
    assert np.abs(p * g).max() <= tol * scale * p.max()
    assert np.allclose(sol.gap_mm, np.where(p > 0, 0.0, g), atol=tol * scale)


def test_converges_to_hertz_on_a_reasonable_grid():
    cells, c, h = hertz_problem(21)
    sol = solve_contact(c, h, cells.area_mm2, LOAD_N)
    assert sol.converged, sol.message
    assert_complementary(c, h, np.ones(h.size), sol)
    a, b = semi_axes_from_moments(cells, sol.pressure_mpa)
    assert a == pytest.approx(HERTZ.semi_axis_x_mm, rel=0.05)
    assert b == pytest.approx(HERTZ.semi_axis_y_mm, rel=0.05)
    assert sol.max_pressure_mpa == pytest.approx(HERTZ.max_pressure_mpa, rel=0.05)
    assert sol.approach_mm == pytest.approx(HERTZ.approach_mm, rel=0.05)
    # the contact set is the ellipse up to the boundary cells
    r = np.sqrt((cells.x_mm / HERTZ.semi_axis_x_mm) ** 2 + (cells.y_mm / HERTZ.semi_axis_y_mm) ** 2)
    cell = max(cells.half_x_mm[0] / HERTZ.semi_axis_x_mm, cells.half_y_mm[0] / HERTZ.semi_axis_y_mm)
    assert sol.in_contact[r < 1 - 2 * cell].all()
    assert not sol.in_contact[r > 1 + 2 * cell].any()
    # cell-resolution extent along x, the semi-axis by the contact edge
    on_x = sol.in_contact & (np.abs(cells.y_mm) < 1e-12)
    extent = np.abs(cells.x_mm[on_x]).max() + cells.half_x_mm[0]
    assert abs(extent - HERTZ.semi_axis_x_mm) <= 2 * cells.half_x_mm[0]


def test_error_decreases_with_refinement():
    errors = []
    for n in (5, 11, 21):
        cells, c, h = hertz_problem(n)
        sol = solve_contact(c, h, cells.area_mm2, LOAD_N)
        assert sol.converged
        a, b = semi_axes_from_moments(cells, sol.pressure_mpa)
        errors.append((abs(sol.max_pressure_mpa / HERTZ.max_pressure_mpa - 1),
                       max(abs(a / HERTZ.semi_axis_x_mm - 1), abs(b / HERTZ.semi_axis_y_mm - 1))))
    p_err = [e[0] for e in errors]
    ax_err = [e[1] for e in errors]
    assert p_err[0] > p_err[1] > p_err[2]
    assert ax_err[2] < ax_err[0] / 5 and ax_err[1] < ax_err[0] / 5
    assert p_err[0] > 0.01 and p_err[2] < 0.002  # visible on the coarse grid, small on the fine


def test_equilibrium_with_moment_weights_and_a_tilted_gap():
    """w = t = r / r_ref: a torque on cells with different moment arms."""
    cells, c, h = hertz_problem(15)
    r_mm = 50.0 + 2.0 * cells.x_mm + 0.5 * cells.y_mm  # moment arms
    r_ref = 50.0
    torque_nmm = 60_000.0
    w = r_mm / r_ref
    tilted = h + 2e-4 * cells.y_mm
    sol = solve_contact(c, tilted, cells.area_mm2, torque_nmm / r_ref, CellWeights(w))
    assert sol.converged, sol.message
    moment = float((cells.area_mm2 * sol.pressure_mpa) @ r_mm)
    assert moment == pytest.approx(torque_nmm, rel=1e-10)
    assert sol.load_residual < 1e-12
    assert_complementary(c, tilted, w, sol)


def test_nonsymmetric_weights_still_solve():
    cells, c, h = hertz_problem(11)
    w = 1.0 + 0.1 * cells.x_mm
    t = 1.0 - 0.2 * cells.y_mm
    sol = solve_contact(c, h, cells.area_mm2, 500.0, CellWeights(w, t))
    assert sol.converged
    assert float((cells.area_mm2 * t) @ sol.pressure_mpa) == pytest.approx(500.0, rel=1e-10)
    assert_complementary(c, h, w, sol)


def test_against_an_independent_qp_solver():
    """min 1/2 f.K.f + h.f, f >= 0, sum f = L in forces f = a p with K = C / a (SLSQP)."""
    cells, c, h = hertz_problem(7, margin=1.6)
    a = cells.area_mm2
    k = c / a[None, :]
    k = 0.5 * (k + k.T)
    res = minimize(lambda f: 0.5 * f @ k @ f + h @ f, np.full(h.size, LOAD_N / h.size),
                   jac=lambda f: k @ f + h, bounds=[(0, None)] * h.size, method="SLSQP",
                   constraints=[{"type": "eq", "fun": lambda f: f.sum() - LOAD_N, "jac": lambda f: np.ones_like(f)}],
                   options={"ftol": 1e-16, "maxiter": 500})
    assert res.success
    sol = solve_contact(c, h, a, LOAD_N)
    assert sol.converged
    assert np.allclose(sol.pressure_mpa * a, res.x, atol=1e-5 * LOAD_N)


def test_block_diagonal_tooth_pairs_share_one_approach():
    """Three identical pairs: two with small, one with large initial separation."""
    cells, c, h = hertz_problem(11, margin=2.0)
    offsets = [0.0, 0.002, 0.5]
    gap = np.concatenate([h + o for o in offsets])
    area = np.tile(cells.area_mm2, 3)
    sol = solve_contact([c, c, c], gap, area, 3 * LOAD_N)
    dense = solve_contact(scipy.linalg.block_diag(c, c, c), gap, area, 3 * LOAD_N)
    prepared = solve_contact(prepare_compliance([c, c, c]), gap, area, 3 * LOAD_N)
    assert sol.converged and dense.converged and prepared.converged
    assert np.allclose(sol.pressure_mpa, dense.pressure_mpa, rtol=1e-9, atol=1e-9)
    assert np.array_equal(sol.pressure_mpa, prepared.pressure_mpa)
    pair_load = (area * sol.pressure_mpa).reshape(3, -1).sum(axis=1)
    assert pair_load.sum() == pytest.approx(3 * LOAD_N, rel=1e-12)
    assert pair_load[0] > pair_load[1] > 0.0 and pair_load[2] == 0.0
    # the unloaded pair keeps its gap minus the approach
    n = cells.size
    assert np.allclose(sol.gap_mm[2 * n:], gap[2 * n:] - sol.approach_mm)


def test_warm_start_and_unconverged_flag():
    cells, c, h = hertz_problem(21)
    cold = solve_contact(c, h, cells.area_mm2, LOAD_N)
    warm = solve_contact(c, h, cells.area_mm2, LOAD_N, initial_contact=cold.in_contact)
    assert warm.converged and warm.iterations == 1
    assert np.array_equal(warm.pressure_mpa, cold.pressure_mpa)
    # a start far from the answer and a single iteration: reported, not hidden
    start = np.zeros(cells.size, dtype=bool)
    start[np.argmin(h)] = True
    cut = solve_contact(c, h, cells.area_mm2, LOAD_N, initial_contact=start, limits=SolveLimits(max_iterations=1))
    assert not cut.converged
    assert "not settled" in cut.message
    assert cut.complementarity_residual > 1e-3


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"load_n": 0.0}, "load_n = 0.0"),
        ({"gap_mm": np.ones(3), "area_mm2": np.ones(3)}, "compliance covers 4 cells but gap_mm has 3"),
        ({"area_mm2": np.array([1.0, 1.0, 0.0, 1.0])}, "area_mm2 has minimum 0.0"),
        ({"weights": CellWeights(-np.ones(4))}, "weights.approach"),
        ({"weights": CellWeights(np.ones(4), np.zeros(4))}, "weights.load"),
        ({"limits": SolveLimits(tolerance=-1.0)}, "tolerance = -1.0"),
        ({"limits": SolveLimits(max_iterations=0)}, "max_iterations = 0"),
        ({"compliance": np.ones((4, 3))}, "must be square"),
        ({"compliance": prepare_compliance(np.eye(5))}, "compliance covers 5 cells but gap_mm has 4"),
    ],
)
def test_user_errors(kwargs, match):
    args = {"compliance": np.eye(4), "gap_mm": np.zeros(4), "area_mm2": np.ones(4), "load_n": 1.0}
    args.update(kwargs)
    c = args.pop("compliance")
    with pytest.raises(ValueError, match=match) as err:
        solve_contact(c, **args)
    assert "\n" not in str(err.value)


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_rough_gaps_with_many_separate_spots(seed):
    """A wavy random gap gives several contact spots; the solution still complements."""
    rng = np.random.default_rng(seed)
    xe = np.linspace(-1.0, 1.0, 17)
    cells = tensor_grid(xe, xe)
    c = tensor_influence_matrix_mm_per_mpa(xe, xe, E_STAR)
    h = cells.x_mm**2 / 40 + cells.y_mm**2 / 100 + rng.normal(0.0, 2e-3, cells.size)
    h -= h.min()
    load = float(10 ** rng.uniform(1, 3.5))
    sol = solve_contact(c, h, cells.area_mm2, load)
    assert sol.converged, sol.message
    assert sol.load_residual < 1e-12
    assert_complementary(c, h, np.ones(h.size), sol)

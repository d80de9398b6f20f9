"""beveloid.ltca.mechanics.halfspace against closed forms and direct quadrature of Boussinesq's 1/r."""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import integrate

from beveloid.ltca.mechanics import halfspace
from beveloid.ltca.mechanics.halfspace import (
    influence_matrix_mm_per_mpa,
    rectangle_cells,
    rectangle_displacement_mm,
    reduced_modulus_mpa,
    tensor_grid,
    tensor_influence_matrix_mm_per_mpa,
)

E_STAR = reduced_modulus_mpa()


def test_reduced_modulus_of_two_steel_bodies_and_of_a_rigid_one():
    assert E_STAR == pytest.approx(206_000.0 / (2 * (1 - 0.09)), rel=1e-14)
    assert reduced_modulus_mpa(210_000.0, 0.28, 1e30, 0.0) == pytest.approx(210_000.0 / (1 - 0.28**2), rel=1e-12)


def test_centre_of_uniformly_loaded_square():
    # Love: u(0) = 8 c p ln(1 + sqrt 2) / (pi E*) for the square |x|, |y| <= c (about 2.24 p c / E*)
    c, p = 0.7, 250.0
    u = rectangle_displacement_mm(0.0, 0.0, c, c, E_STAR, p)
    assert u == pytest.approx(8 * c * p * math.log(1 + math.sqrt(2)) / (math.pi * E_STAR), rel=1e-13)
    assert u * E_STAR / (p * c) == pytest.approx(2.2443, abs=1e-4)


@pytest.mark.parametrize("x, y", [(0.3, 0.2), (2.5, -1.0), (1.0, 0.5), (-0.9, 0.49), (0.0, 3.0)])
def test_matches_quadrature_of_the_point_force_solution(x, y):
    hx, hy = 1.0, 0.5

    def inv_r(eta, xi):
        return 1.0 / math.hypot(xi - x, eta - y)

    q, _ = integrate.dblquad(inv_r, -hx, hx, -hy, hy, epsabs=1e-12, epsrel=1e-11)
    assert rectangle_displacement_mm(x, y, hx, hy, E_STAR) == pytest.approx(q / (math.pi * E_STAR), rel=1e-8)


def test_far_field_is_a_point_force():
    r = 400.0
    u = rectangle_displacement_mm(r, 0.0, 0.5, 0.25, E_STAR, 1.0)
    force = 4 * 0.5 * 0.25
    assert u == pytest.approx(force / (math.pi * E_STAR * r), rel=1e-5)


def test_tensor_builder_equals_general_builder_uniform_and_nonuniform():
    rng = np.random.default_rng(3)
    for xe, ye in [
        (np.linspace(-1.0, 2.0, 9), np.linspace(0.0, 1.0, 6)),
        (np.cumsum(rng.uniform(0.1, 1.0, 8)), np.cumsum(rng.uniform(0.2, 1.0, 5))),
    ]:
        general = influence_matrix_mm_per_mpa(tensor_grid(xe, ye), E_STAR)
        fast = tensor_influence_matrix_mm_per_mpa(xe, ye, E_STAR)
        assert np.allclose(fast, general, rtol=1e-12, atol=0.0)


@pytest.mark.parametrize("nx, ny", [(11, 17), (1, 1), (2, 5)])
def test_uniform_table_from_one_quarter_is_the_table_of_every_offset(nx, ny):
    """uniform_influence_table evaluates G on the positive offsets and mirrors it (G is odd in u and in v): the
    same numbers, to the last bit, as G evaluated at every offset (+-1/2 .. nx - 1/2 cells)."""
    rng = np.random.default_rng(nx)
    dx, dy = rng.uniform(0.01, 2.0, 40), rng.uniform(0.01, 5.0, 40)
    u = (np.arange(-(nx - 1), nx + 1) - 0.5)[None, :] * dx[:, None]
    v = (np.arange(-(ny - 1), ny + 1) - 0.5)[None, :] * dy[:, None]
    t = halfspace._g(u[:, :, None], v[:, None, :])
    every = (t[:, 1:, 1:] - t[:, :-1, 1:] - t[:, 1:, :-1] + t[:, :-1, :-1]) / (np.pi * E_STAR)
    assert np.array_equal(halfspace.uniform_influence_table(dx, dy, nx, ny, E_STAR), every)


def test_uniform_grid_matrix_is_symmetric_and_positive_definite():
    c = tensor_influence_matrix_mm_per_mpa(np.linspace(0, 2, 11), np.linspace(0, 1, 7), E_STAR)
    assert np.allclose(c, c.T, rtol=1e-13, atol=0.0)
    assert np.linalg.eigvalsh(c).min() > 0.0


def test_list_of_rectangles_and_targets():
    cells = rectangle_cells([0.0, 3.0], [0.0, 1.0], [0.5, 0.2], [0.25, 0.4])
    assert np.allclose(cells.area_mm2, [0.5, 0.32])
    targets = rectangle_cells([1.0], [2.0], [0.1], [0.1])
    c = influence_matrix_mm_per_mpa(cells, E_STAR, targets)
    assert c.shape == (1, 2)
    assert c[0, 1] == pytest.approx(rectangle_displacement_mm(1.0 - 3.0, 2.0 - 1.0, 0.2, 0.4, E_STAR), rel=1e-14)


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: reduced_modulus_mpa(nu1=0.5), "nu1 = 0.5"),
        (lambda: reduced_modulus_mpa(e2_mpa=-1.0), "e2_mpa = -1.0"),
        (lambda: tensor_grid([0.0, 1.0, 0.5], [0.0, 1.0]), "x_edges_mm"),
        (lambda: rectangle_cells([0.0], [0.0], [0.0], [1.0]), "half_x_mm"),
        (lambda: rectangle_cells([0.0, 1.0], [0.0], [1.0], [1.0]), "y_mm has 1 entries"),
        (lambda: rectangle_displacement_mm(0, 0, 1, 1, float("nan")), "e_star_mpa = nan"),
    ],
)
def test_user_errors_are_one_line_value_errors(call, match):
    with pytest.raises(ValueError, match=match) as err:
        call()
    assert "\n" not in str(err.value)

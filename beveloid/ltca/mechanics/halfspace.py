"""Boussinesq influence coefficients for uniformly loaded rectangles on an elastic half-space.

A normal point force P on the surface of a linear elastic half-space moves the surface
point at distance r by u_z = (1 - nu^2) P / (pi E r) (Boussinesq).  Two bodies pressed
together close their gap by the sum of both displacements, so only the combined
(reduced) modulus enters::

    1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2.

Integrating the point-force solution over a rectangle carrying a uniform pressure p gives
Love's (1929) closed form; with u = xi - x, v = eta - y measured from the field point::

    u_z(x, y) = p / (pi E*) * [G(u, v)] evaluated between the rectangle's corners
    G(u, v)   = u asinh(v / |u|) + v asinh(u / |v|)      (G = 0 on u = 0 or v = 0 terms)

where [G] = G(u2, v2) - G(u1, v2) - G(u2, v1) + G(u1, v1).  G is an antiderivative of
1/sqrt(u^2 + v^2) in both variables (d2G/du dv = 1/r); terms depending on u alone or v
alone cancel in the double difference.  The derivation is in docs/loaded_contact.md.

Cells are axis-aligned rectangles in a plane (the tangent plane of the contact), given by
centre and half widths; a tensor-product grid is one way to make them.  Units: mm, N, MPa;
an influence matrix maps cell pressures (MPa) to displacements at cell centres (mm).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import checks

__all__ = [
    "STEEL_E_MPA",
    "STEEL_NU",
    "Cells",
    "rectangle_cells",
    "tensor_grid",
    "reduced_modulus_mpa",
    "rectangle_displacement_mm",
    "influence_matrix_mm_per_mpa",
    "tensor_influence_matrix_mm_per_mpa",
]

STEEL_E_MPA = 206_000.0
STEEL_NU = 0.3


@dataclass(frozen=True)
class Cells:
    """Axis-aligned rectangular cells: centres and half widths (mm), one entry per cell."""

    x_mm: np.ndarray
    y_mm: np.ndarray
    half_x_mm: np.ndarray
    half_y_mm: np.ndarray

    @property
    def size(self) -> int:
        return int(self.x_mm.size)

    @property
    def area_mm2(self) -> np.ndarray:
        return 4.0 * self.half_x_mm * self.half_y_mm


def rectangle_cells(x_mm, y_mm, half_x_mm, half_y_mm) -> Cells:
    """Cells from centre coordinates and half widths (1-D arrays of one length, half widths > 0)."""
    x = checks.finite_array("x_mm", x_mm)
    n = x.size
    return Cells(
        x_mm=x,
        y_mm=checks.finite_array("y_mm", y_mm, n),
        half_x_mm=checks.finite_array("half_x_mm", half_x_mm, n, positive_only=True),
        half_y_mm=checks.finite_array("half_y_mm", half_y_mm, n, positive_only=True),
    )


def tensor_grid(x_edges_mm, y_edges_mm) -> Cells:
    """Cells of the tensor-product grid with the given (strictly increasing) cell edges.

    Cell k = i * ny + j covers [x_i, x_i+1] x [y_j, y_j+1]: a cell field ``f`` reshapes to
    ``f.reshape(nx, ny)`` with x along the first axis.
    """
    xe = checks.finite_array("x_edges_mm", x_edges_mm)
    ye = checks.finite_array("y_edges_mm", y_edges_mm)
    for name, e in (("x_edges_mm", xe), ("y_edges_mm", ye)):
        if e.size < 2 or not np.all(np.diff(e) > 0):
            raise ValueError(f"{name} = {e!r}: must be at least 2 strictly increasing edges")
    xc, yc = 0.5 * (xe[1:] + xe[:-1]), 0.5 * (ye[1:] + ye[:-1])
    hx, hy = 0.5 * np.diff(xe), 0.5 * np.diff(ye)
    X, Y = np.meshgrid(xc, yc, indexing="ij")
    HX, HY = np.meshgrid(hx, hy, indexing="ij")
    return Cells(X.ravel(), Y.ravel(), HX.ravel(), HY.ravel())


def reduced_modulus_mpa(
    e1_mpa: float = STEEL_E_MPA, nu1: float = STEEL_NU, e2_mpa: float = STEEL_E_MPA, nu2: float = STEEL_NU
) -> float:
    """E* with 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2 (MPa); defaults: two steel bodies."""
    e1, e2 = checks.positive("e1_mpa", e1_mpa), checks.positive("e2_mpa", e2_mpa)
    n1, n2 = checks.poisson("nu1", nu1), checks.poisson("nu2", nu2)
    return 1.0 / ((1.0 - n1 * n1) / e1 + (1.0 - n2 * n2) / e2)


def _g(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """u asinh(v/|u|) + v asinh(u/|v|), each term 0 where its prefactor is 0."""
    au, av = np.abs(u), np.abs(v)
    with np.errstate(divide="ignore", invalid="ignore"):
        t1 = np.where(au > 0.0, u * np.arcsinh(v / np.where(au > 0.0, au, 1.0)), 0.0)
        t2 = np.where(av > 0.0, v * np.arcsinh(u / np.where(av > 0.0, av, 1.0)), 0.0)
    return t1 + t2


def _unit_kernel(dx: np.ndarray, dy: np.ndarray, hx: np.ndarray, hy: np.ndarray) -> np.ndarray:
    """Integral of 1/r over the rectangle centred at offset (dx, dy) from the field point, half widths hx, hy."""
    u1, u2 = dx - hx, dx + hx
    v1, v2 = dy - hy, dy + hy
    return _g(u2, v2) - _g(u1, v2) - _g(u2, v1) + _g(u1, v1)


def rectangle_displacement_mm(
    x_mm, y_mm, half_x_mm: float, half_y_mm: float, e_star_mpa: float, pressure_mpa: float = 1.0
) -> np.ndarray:
    """Gap closure (mm) at points (x, y) by a pressure on the rectangle |x| <= hx, |y| <= hy.

    Both bodies together (E* from :func:`reduced_modulus_mpa`); points may lie inside or outside.
    """
    hx, hy = checks.positive("half_x_mm", half_x_mm), checks.positive("half_y_mm", half_y_mm)
    es = checks.positive("e_star_mpa", e_star_mpa)
    x, y = np.asarray(x_mm, dtype=float), np.asarray(y_mm, dtype=float)
    return float(pressure_mpa) / (np.pi * es) * _unit_kernel(-x, -y, hx, hy)


def influence_matrix_mm_per_mpa(cells: Cells, e_star_mpa: float, targets: Cells | None = None) -> np.ndarray:
    """C[i, j]: gap closure (mm) at the centre of target cell i per MPa on source cell j.

    ``targets`` defaults to ``cells`` (square matrix).  Dense, float64, O(n_targets n_cells)
    memory.  On a uniform grid C is symmetric.  On a non-uniform grid it is not, and
    C[i, j]/area[j] is only nearly symmetric: reciprocity holds for forces, and centre
    collocation breaks it slightly.
    """
    es = checks.positive("e_star_mpa", e_star_mpa)
    t = cells if targets is None else targets
    dx = cells.x_mm[None, :] - t.x_mm[:, None]
    dy = cells.y_mm[None, :] - t.y_mm[:, None]
    k = _unit_kernel(dx, dy, cells.half_x_mm[None, :], cells.half_y_mm[None, :])
    k *= 1.0 / (np.pi * es)
    return k


def _is_uniform(edges: np.ndarray) -> bool:
    d = np.diff(edges)
    return bool(np.allclose(d, d[0], rtol=1e-12, atol=0.0))


def tensor_influence_matrix_mm_per_mpa(x_edges_mm, y_edges_mm, e_star_mpa: float) -> np.ndarray:
    """:func:`influence_matrix_mm_per_mpa` of ``tensor_grid(x_edges_mm, y_edges_mm)``, faster.

    The corner terms G(u, v) of a tensor grid take u from a 1-D set (x edges minus x
    centres) and v likewise, so G is tabulated once per (u, v) pair instead of four times
    per matrix entry; on a uniform grid the matrix is Toeplitz in both directions and G
    is tabulated on the (2 nx) x (2 ny) offsets only.
    """
    cells = tensor_grid(x_edges_mm, y_edges_mm)  # validates the edges
    es = checks.positive("e_star_mpa", e_star_mpa)
    xe, ye = np.asarray(x_edges_mm, dtype=float), np.asarray(y_edges_mm, dtype=float)
    nx, ny = xe.size - 1, ye.size - 1
    if _is_uniform(xe) and _is_uniform(ye):
        return uniform_influence_blocks(xe[1] - xe[0], ye[1] - ye[0], nx, ny, es)[0]
    xc, yc = 0.5 * (xe[1:] + xe[:-1]), 0.5 * (ye[1:] + ye[:-1])
    u = xe[None, :] - xc[:, None]  # (nx, nx + 1): target i, edge k'
    v = ye[None, :] - yc[:, None]  # (ny, ny + 1)
    t = _g(u[:, :, None, None], v[None, None, :, :])  # (i, k', j, l')
    d = t[:, 1:, :, 1:] - t[:, :-1, :, 1:] - t[:, 1:, :, :-1] + t[:, :-1, :, :-1]  # (i, k, j, l)
    c = d.transpose(0, 2, 1, 3)
    n = cells.size
    return np.ascontiguousarray(c.reshape(n, n)) / (np.pi * es)


def uniform_influence_table(dx_mm, dy_mm, nx: int, ny: int, e_star_mpa: float) -> np.ndarray:
    """(Q, 2 nx - 1, 2 ny - 1) the Toeplitz table of Q uniform nx x ny tensor grids of cell sizes
    ``dx_mm`` (Q,) x ``dy_mm`` (Q,): entry [a + nx - 1, b + ny - 1] is the closure (mm/MPa) at a cell
    centre by a unit pressure on the cell a cells across and b cells along from it.  The corner terms
    G(u, v) are tabulated on the (2 nx) x (2 ny) offsets of each grid only, all grids at once."""
    dx, dy = np.atleast_1d(np.asarray(dx_mm, dtype=float)), np.atleast_1d(np.asarray(dy_mm, dtype=float))
    # u = x_edge[k'] - x_centre[i] = (k' - i - 1/2) dx for k' - i = -(nx - 1) .. nx: +-(1/2 .. nx - 1/2) dx, none 0.
    # G is odd in u and in v (asinh is odd): G is evaluated on the positive quarter only, the other three its
    # mirror images with their signs (the same numbers as G at the negative offsets: every step is exact
    # under a change of sign)
    u = (np.arange(nx) + 0.5)[None, :] * dx[:, None]
    v = (np.arange(ny) + 0.5)[None, :] * dy[:, None]
    uu, vv = u[:, :, None], v[:, None, :]
    g = uu * np.arcsinh(vv / uu) + vv * np.arcsinh(uu / vv)  # (Q, nx, ny): G at (+u, +v)
    t = np.empty((g.shape[0], 2 * nx, 2 * ny))
    t[:, nx:, ny:] = g
    t[:, :nx, ny:] = -g[:, ::-1, :]
    t[:, nx:, :ny] = -g[:, :, ::-1]
    t[:, :nx, :ny] = g[:, ::-1, ::-1]
    return (t[:, 1:, 1:] - t[:, :-1, 1:] - t[:, 1:, :-1] + t[:, :-1, :-1]) / (np.pi * e_star_mpa)


def uniform_influence_blocks(dx_mm, dy_mm, nx: int, ny: int, e_star_mpa: float) -> np.ndarray:
    """(Q, n, n) :func:`influence_matrix_mm_per_mpa` of Q uniform nx x ny tensor grids (cells
    i * ny + j) from :func:`uniform_influence_table`: Toeplitz in both directions."""
    d = uniform_influence_table(dx_mm, dy_mm, nx, ny, e_star_mpa)
    i = np.arange(nx)
    j = np.arange(ny)
    a = (i[None, None, :, None] - i[:, None, None, None]) + nx - 1
    b = (j[None, None, None, :] - j[None, :, None, None]) + ny - 1
    n = nx * ny
    return d[:, a, b].reshape(d.shape[0], n, n)

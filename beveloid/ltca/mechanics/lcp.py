"""Normal contact with a rigid approach: the linear complementarity problem of LTCA.

Find cell pressures p >= 0 (MPa) and one rigid approach delta (mm) such that

    g_i = h_i - delta w_i + (C p)_i >= 0,      p_i g_i = 0,      sum_i a_i t_i p_i = L

h: unloaded gap (mm), C: compliance (mm per MPa, cell pressures to displacements at cell
centres), a: cell areas (mm^2), w: approach weights, t: load weights (both dimensionless),
L: load (N).  With w = t = 1 this is a body pressed by a force L.  For a torque, divide the
moment arms r_i by a reference radius r_ref: w = t = r_i / r_ref, L = T / r_ref and delta /
r_ref is the rigid rotation (virtual work makes w = t the consistent choice; other t are
accepted).  Several tooth pairs that share one rigid rotation are one problem with a
block-diagonal C: pass the blocks as a list and the cells in block order.

Method: a primal-dual active-set method (Kalker's active set; the same fixed point as
the Conry-Seireg simplex formulation).  On a trial contact set S it solves exactly

    C_SS p_S - delta w_S = -h_S,     sum_S a t p_S = L

(one factorisation of C_SS per block, the shared delta by a Schur complement), then
drops the cells of S with p < 0 and adds the cells outside S with g < 0.  It stops when
S no longer changes; the equilibrium holds to rounding at every iterate.  If a set
repeats (cycling), it changes one cell per iteration (the most violated), as in Murty's
principal pivoting.  The result says whether it converged; nothing is silently clipped.
"""
from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Sequence

import typing

import numpy as np

from . import checks, kernel

__all__ = ["CellWeights", "Compliance", "ContactSolution", "SolveLimits", "prepare_compliance", "solve_contact"]


@dataclass(frozen=True)
class ContactSolution:
    """Solution of :func:`solve_contact` and how well it satisfies the problem.

    ``complementarity_residual``: the largest of max(-p)/max(p), max(-g)/d and
    max(|p g|)/(max(p) d), with d the largest elastic displacement |C p|.
    ``load_residual``: |sum a t p - L| / L.  ``converged`` is True only when the active
    set settled and both residuals are within the requested tolerances.
    """

    pressure_mpa: np.ndarray
    gap_mm: np.ndarray
    approach_mm: float
    converged: bool
    iterations: int
    complementarity_residual: float
    load_residual: float
    message: str
    area_mm2: np.ndarray

    @property
    def in_contact(self) -> np.ndarray:
        return self.pressure_mpa > 0.0

    @property
    def contact_area_mm2(self) -> float:
        return float(self.area_mm2[self.in_contact].sum())

    @property
    def max_pressure_mpa(self) -> float:
        return float(self.pressure_mpa.max()) if self.pressure_mpa.size else 0.0


class SolveLimits(typing.NamedTuple):
    """When :func:`solve_contact` stops: the complementarity residual's relative ``tolerance`` and
    the most active-set ``max_iterations``."""

    tolerance: float = 1e-10
    max_iterations: int = 200


@dataclass(frozen=True)
class Compliance:
    """A checked compliance (mm per MPa): square blocks on the diagonal, cells in block order.

    Build it once per grid with :func:`prepare_compliance` and pass it to every
    :func:`solve_contact` of that grid: the O(n^2) checks are then not repeated.
    """

    blocks: tuple
    slices: tuple
    symmetric: tuple

    @property
    def size(self) -> int:
        return self.slices[-1].stop

    def diagonal(self) -> np.ndarray:
        """The diagonal of C (all blocks, in cell order)."""
        return np.concatenate([np.diag(b) for b in self.blocks])

    @functools.cached_property
    def flat(self):
        """(blocks, off, start, size, sym): the blocks one after the other in one flat array, the
        layout :mod:`beveloid.ltca.mechanics.kernel` reads (made once per Compliance)."""
        size = np.array([b.shape[0] for b in self.blocks], dtype=np.int64)
        start = np.array([sl.start for sl in self.slices], dtype=np.int64)
        off = np.concatenate([[0], np.cumsum(size * size)[:-1]]).astype(np.int64)
        return (np.concatenate([b.ravel() for b in self.blocks]), off, start, size,
                np.array(self.symmetric, dtype=np.bool_))


def prepare_compliance(compliance_mm_per_mpa: np.ndarray | Sequence[np.ndarray] | Compliance) -> Compliance:
    """Check a dense matrix or a list of square diagonal blocks once (finite, diagonal > 0, symmetry)."""
    if isinstance(compliance_mm_per_mpa, Compliance):
        return compliance_mm_per_mpa
    raw = compliance_mm_per_mpa
    blocks = [raw] if isinstance(raw, np.ndarray) else list(raw)
    if not blocks:
        raise ValueError("compliance_mm_per_mpa = []: must be a square matrix or a non-empty list of them")
    out, slices, sym = [], [], []
    start = 0
    for k, b in enumerate(blocks):
        b = np.ascontiguousarray(b, dtype=float)
        if b.ndim != 2 or b.shape[0] != b.shape[1]:
            raise ValueError(f"compliance block {k} has shape {b.shape}: must be square")
        if not np.all(np.isfinite(b)):
            raise ValueError(f"compliance block {k} contains non-finite values: every entry must be finite")
        if not np.all(np.diag(b) > 0.0):
            raise ValueError(f"compliance block {k} has a diagonal entry <= 0: every diagonal entry must be > 0")
        out.append(b)
        slices.append(slice(start, start + b.shape[0]))
        sym.append(bool(np.allclose(b, b.T, rtol=1e-12, atol=0.0)))
        start += b.shape[0]
    return Compliance(tuple(out), tuple(slices), tuple(sym))


class CellWeights(typing.NamedTuple):
    """The weights of the module docstring, one entry per cell (both > 0): w (approach) and t (load; None:
    t = w)."""

    approach: typing.Any
    load: typing.Any = None


def solve_contact(
    compliance_mm_per_mpa: np.ndarray | Sequence[np.ndarray] | Compliance,
    gap_mm,
    area_mm2,
    load_n: float,
    weights: CellWeights | None = None,
    *,
    initial_contact=None,
    limits: "SolveLimits | None" = None,
    solver=None,
) -> ContactSolution:
    """Solve the contact problem of the module docstring.

    ``compliance_mm_per_mpa``: an (n, n) matrix, a list of square blocks (block-diagonal,
    cells in block order) or a :class:`Compliance` from :func:`prepare_compliance`
    (checked once; use it when solving many positions on one grid).  ``gap_mm``, ``area_mm2``: one entry
    per cell.  ``weights``: :class:`CellWeights` (w, t), None: w = t = 1.  ``initial_contact``: optional boolean start set (e.g. the previous mesh
    position); by default an uncoupled-spring estimate.  ``limits``: :class:`SolveLimits`, the
    relative tolerance of the complementarity residual (the load residual is held to 1e-9 at most)
    and the most active-set iterations.  ``solver``: a :class:`beveloid.solver.Solver` (its backend:
    the kernel compiled or interpreted), None the default solver.
    """
    h = checks.finite_array("gap_mm", gap_mm)
    n = h.size
    if n == 0:
        raise ValueError("gap_mm is empty: must have at least one cell")
    a = checks.finite_array("area_mm2", area_mm2, n, positive_only=True)
    load = checks.positive("load_n", load_n)
    weights = CellWeights(None) if weights is None else weights
    w = np.ones(n) if weights.approach is None else checks.finite_array("weights.approach", weights.approach, n, True)
    t = w if weights.load is None else checks.finite_array("weights.load", weights.load, n, True)
    limits = SolveLimits() if limits is None else limits
    tol, max_iterations = checks.positive("tolerance", limits.tolerance), limits.max_iterations
    if not (isinstance(max_iterations, int) and max_iterations >= 1):
        raise ValueError(f"max_iterations = {max_iterations!r}: must be an integer >= 1")
    ops = prepare_compliance(compliance_mm_per_mpa)
    if ops.size != n:
        raise ValueError(f"compliance covers {ops.size} cells but gap_mm has {n}: they must match")
    at = a * t
    from ...solver import Solver

    k = kernel.kernels(Solver.of(solver))
    if initial_contact is None:
        active = np.zeros(n, dtype=bool)
    else:
        active = np.asarray(initial_contact, dtype=bool)
        if active.shape != (n,):
            raise ValueError(f"initial_contact has shape {active.shape}: must be ({n},) booleans")
    blocks, off, start, size, sym = ops.flat
    p = np.zeros((1, n))
    results = np.zeros((1, 5))
    k.solve_positions(kernel.Layout(blocks, off[None], start, size, sym[None], kernel.given(1, size)),
                      kernel.Cells(h[None], w[None], at[None], np.array([float(load)])),
                      kernel.Start(float(tol), int(max_iterations), np.ascontiguousarray(active[None]),
                                   np.array([initial_contact is not None])),
                      kernel.Output(p, results))
    p, result = p[0], results[0]
    delta, it, code, comp, load_res = result
    code = int(code)
    elastic = np.concatenate([b @ p[sl] for b, sl in zip(ops.blocks, ops.slices)])
    message = {0: "converged", 1: f"active set not settled after {max_iterations} iterations",
               2: f"settled but residuals too large (complementarity {comp:.2e}, load {load_res:.2e})",
               3: "singular trial contact set (load weights against approach response <= 0)",
               4: "empty contact set"}[code]
    return ContactSolution(pressure_mpa=p, gap_mm=np.where(p > 0.0, 0.0, h - delta * w + elastic),
                           approach_mm=float(delta), converged=code == 0, iterations=int(it),
                           complementarity_residual=float(comp), load_residual=float(load_res), message=message,
                           area_mm2=a)

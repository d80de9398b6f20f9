"""The active-set contact solve of :mod:`beveloid.ltca.mechanics.lcp`, plain Python in numba's subset: one
implementation, run interpreted (the numpy backend) or compiled by numba (:func:`kernels`).

A problem is a block-diagonal compliance given as dense square blocks stored one after the other
in a flat array (:class:`Layout`), each block symmetric (Cholesky, else Gaussian elimination with
partial pivoting; a symmetric block that is not positive definite is solved by elimination too) or
not.  :func:`active_set` solves one problem (the method: lcp.py's docstring); :func:`solve_positions`,
the entry point, solves many problems of equal block layout (the LTCA's mesh positions; one for
``lcp.solve_contact``) in one call.  Its arguments are the records below (numba reads named tuples).

Result codes (``STATUS``): 0 converged, 1 the active set did not settle within the iterations,
2 settled but the residuals are too large, 3 a singular trial set, 4 an empty contact set.
"""
from __future__ import annotations

import math
import sys
import typing

import numpy as np

STATUS = ("converged", "not settled", "residuals too large", "singular trial contact set", "empty contact set")
TINY = 2.2250738585072014e-308  # numpy.finfo(float).tiny
#: the load residual a converged solve holds (relative)
LOAD_TOL = 1e-9


class Rows(typing.NamedTuple):
    """Where the rows of the blocks come from when they are not given: a row is made (:func:`_row`) when its
    cell first enters a trial set, and the solve reads no other (the rows of the trial sets' cells; the
    initial set reads the diagonal, :func:`_diagonal`).  Problem j's block b (q = j nb + b) is the half-space
    part of a uniform nx x ny grid, its Toeplitz table ``halfspace[q]`` (2 nx - 1, 2 ny - 1) (cell (i, j)
    loaded by cell (k, l) at [k - i + nx - 1, l - j + ny - 1]), plus the tooth line compliance ``tooth[q]``
    (ny, ny) (at [j, l]) times the cell area ``area[q]``; where not ``loaded[q]`` a unit diagonal (a block
    whose cells are never active).  ``built[q, r]`` when row r of block q is in the blocks (all true: the
    blocks given whole, :func:`given`)."""

    halfspace: np.ndarray  # (Q, 2 nx - 1, 2 ny - 1)
    tooth: np.ndarray  # (Q, ny, ny)
    area: np.ndarray  # (Q,)
    loaded: np.ndarray  # (Q,) bool
    built: np.ndarray  # (Q, the largest block) bool


def given(J, size):
    """:class:`Rows` of blocks given whole: J problems of blocks of the sizes ``size``."""
    return Rows(np.zeros((1, 1, 1)), np.zeros((1, 1, 1)), np.ones(1), np.ones(1, dtype=np.bool_),
                np.ones((J * len(size), max(int(np.max(size)), 1)), dtype=np.bool_))


class Layout(typing.NamedTuple):
    """The compliance of J problems of one block layout: problem j's block b is ``size[b]`` x ``size[b]``
    entries of ``blocks`` row-major from ``off[j, b]``, over its cells ``start[b]`` .. ``start[b] +
    size[b]``; ``sym[j, b]`` when it is symmetric; ``rows`` (:class:`Rows`) where the rows not yet in
    ``blocks`` come from."""

    blocks: np.ndarray  # flat, float
    off: np.ndarray  # (J, blocks) int64
    start: np.ndarray  # (blocks,) int64
    size: np.ndarray  # (blocks,) int64
    sym: np.ndarray  # (J, blocks) bool
    rows: Rows


class Cells(typing.NamedTuple):
    """The cells of J problems (lcp.py's docstring): unloaded gap ``h`` (mm), approach weight ``w``, cell
    area times load weight ``at`` (mm^2), each (J, n), and each problem's ``load`` (N) (J,)."""

    h: np.ndarray
    w: np.ndarray
    at: np.ndarray
    load: np.ndarray


class Start(typing.NamedTuple):
    """How the iterations run: the complementarity residual's relative ``tolerance``, the most
    ``max_iterations``, and each problem's start set: ``starts[j]`` (J, n) where ``given[j]`` and it
    holds a cell, else the uncoupled estimate (:func:`initial_set`; ``starts`` may then be (J, 1))."""

    tolerance: float
    max_iterations: int
    starts: np.ndarray
    given: np.ndarray


class Output(typing.NamedTuple):
    """Where :func:`solve_positions` writes: the cell pressures (J, n) (MPa) and per problem (J, 5) the
    approach (mm), the iterations, the status code (``STATUS``), the complementarity and load residuals."""

    pressure: np.ndarray
    result: np.ndarray


class Work(typing.NamedTuple):
    """Scratch of one block's solve (:func:`_factor_solve`), room for the largest block (m cells): the
    trial set's cell indices, the two right-hand sides, the two solutions, the factor."""

    idx: np.ndarray  # (m,) int64
    rhs: np.ndarray  # (m, 2)
    sol: np.ndarray  # (m, 2)
    factor: np.ndarray  # (m, m)


def _row(blocks, o, rows, q, r):
    """Row r of block q (at offset o of ``blocks``) from its tables (:class:`Rows`); its callers test
    ``rows.built[q, r]`` first (the test costs less than the call)."""
    rows.built[q, r] = True
    d, t = rows.halfspace[q], rows.tooth[q]
    ny = t.shape[0]
    nx = (d.shape[0] + 1) // 2
    n = nx * ny
    base = o + r * n
    if not rows.loaded[q]:
        for k in range(n):
            blocks[base + k] = 0.0
        blocks[base + r] = 1.0
        return
    a = rows.area[q]
    i = r // ny
    j = r - i * ny
    for k in range(nx):
        for m in range(ny):
            blocks[base + k * ny + m] = d[k - i + nx - 1, m - j + ny - 1] + t[j, m] * a


def _diagonal(rows, q, out):
    """The diagonal of block q, none of its rows made yet, into ``out``: as :func:`_row` makes it."""
    if not rows.loaded[q]:
        for r in range(out.size):
            out[r] = 1.0
        return
    d, t, a = rows.halfspace[q], rows.tooth[q], rows.area[q]
    ny = t.shape[0]
    nx = (d.shape[0] + 1) // 2
    for r in range(out.size):
        j = r - (r // ny) * ny
        out[r] = d[nx - 1, ny - 1] + t[j, j] * a


def _dot(a, i, j, n):
    """sum_k<n a[i, k] a[j, k], in four running sums (the order is fixed: the same on every backend)."""
    s0 = s1 = s2 = s3 = 0.0
    k = 0
    while k + 4 <= n:
        s0 += a[i, k] * a[j, k]
        s1 += a[i, k + 1] * a[j, k + 1]
        s2 += a[i, k + 2] * a[j, k + 2]
        s3 += a[i, k + 3] * a[j, k + 3]
        k += 4
    while k < n:
        s0 += a[i, k] * a[j, k]
        k += 1
    return (s0 + s1) + (s2 + s3)


def _factor_solve(blocks, o, s, m, sym, wk):
    """wk.sol[:m, :] = C[idx, idx]^-1 wk.rhs[:m, :] (2 right-hand sides; idx = wk.idx[:m]) for the block
    at offset o of ``blocks`` (size s); False when singular."""
    idx, rhs, out, work = wk.idx, wk.rhs, wk.sol, wk.factor
    for a in range(m):
        for b in range(m):
            work[a, b] = blocks[o + idx[a] * s + idx[b]]
    ok = False
    if sym:
        ok = True
        for j in range(m):  # Cholesky, lower triangle in place
            d = work[j, j] - _dot(work, j, j, j)
            if not d > 0.0:
                ok = False
                break
            d = math.sqrt(d)
            work[j, j] = d
            for i in range(j + 1, m):
                work[i, j] = (work[i, j] - _dot(work, i, j, j)) / d
        if ok:
            for c in range(2):
                for i in range(m):
                    v = rhs[i, c]
                    for k in range(i):
                        v -= work[i, k] * out[k, c]
                    out[i, c] = v / work[i, i]
                for i in range(m - 1, -1, -1):
                    v = out[i, c]
                    for k in range(i + 1, m):
                        v -= work[k, i] * out[k, c]
                    out[i, c] = v / work[i, i]
            return True
        for a in range(m):
            for b in range(m):
                work[a, b] = blocks[o + idx[a] * s + idx[b]]
    for i in range(m):
        out[i, 0] = rhs[i, 0]
        out[i, 1] = rhs[i, 1]
    for j in range(m):  # Gaussian elimination with partial pivoting
        piv = j
        big = abs(work[j, j])
        for i in range(j + 1, m):
            if abs(work[i, j]) > big:
                big = abs(work[i, j])
                piv = i
        if not big > 0.0:
            return False
        if piv != j:
            for k in range(m):
                t = work[j, k]
                work[j, k] = work[piv, k]
                work[piv, k] = t
            for c in range(2):
                t = out[j, c]
                out[j, c] = out[piv, c]
                out[piv, c] = t
        for i in range(j + 1, m):
            f = work[i, j] / work[j, j]
            if f != 0.0:
                for k in range(j, m):
                    work[i, k] -= f * work[j, k]
                out[i, 0] -= f * out[j, 0]
                out[i, 1] -= f * out[j, 1]
    for c in range(2):
        for i in range(m - 1, -1, -1):
            v = out[i, c]
            for k in range(i + 1, m):
                v -= work[i, k] * out[k, c]
            out[i, c] = v / work[i, i]
    return True


def _matvec(layout, jp, active, p, out):
    """out = C[:, S] p_S (S the active cells) of problem jp of the :class:`Layout` ``layout``, block by block,
    over the active columns only: a symmetric block adds its active rows (C[j, :] = C[:, j], made by
    :func:`_row`) times p_j, a contiguous pass each; another (given whole) sums each row over the active
    columns."""
    blocks, off, start, size, sym, rows = (layout.blocks, layout.off[jp], layout.start, layout.size, layout.sym[jp],
                                           layout.rows)
    q0 = jp * off.size
    cols = np.empty(p.size, dtype=np.int64)
    built = rows.built
    for b in range(off.size):
        o, s0, s = off[b], start[b], size[b]
        if sym[b]:
            for i in range(s):
                out[s0 + i] = 0.0
            for j in range(s):
                if active[s0 + j]:
                    if not built[q0 + b, j]:
                        _row(blocks, o, rows, q0 + b, j)
                    v = p[s0 + j]
                    row = o + j * s
                    for i in range(s):
                        out[s0 + i] += blocks[row + i] * v
            continue
        m = 0
        for j in range(s):
            if active[s0 + j]:
                cols[m] = j
                m += 1
        for i in range(s):
            v = 0.0
            row = o + i * s
            for c in range(m):
                v += blocks[row + cols[c]] * p[s0 + cols[c]]
            out[s0 + i] = v


def initial_set(h, w, diag, at, load, active):
    """The contact set of an uncoupled (Winkler) model, p_i = max(0, (delta w_i - h_i))/(k C_ii), into
    ``active``: k = 3 softens the springs for the neighbours' share of the deflection; the set is
    only a start and the iteration corrects it.  delta follows from the load by sorting."""
    n = h.size
    s = h / w
    order = np.argsort(s, kind="quicksort")
    cum_c = 0.0
    cum_cs = 0.0
    j = n - 1
    for r in range(n):
        i = order[r]
        c = at[i] * w[i] / (3.0 * diag[i])  # load per unit (delta - s_i) from cell i
        cum_c += c
        cum_cs += c * s[i]
        # load(delta) with the first r cells active = delta cum_c - cum_cs, for s_r <= delta <= s_r+1
        delta = (load + cum_cs) / cum_c
        nxt = s[order[r + 1]] if r + 1 < n else np.inf
        if delta >= s[i] and delta <= nxt:
            j = r
            break
    for r in range(n):
        active[order[r]] = r <= j


def active_set(layout, cells, j, limits, active, out, seen):
    """Solve problem j (module docstring) from the start set ``active`` (changed in place), the
    :class:`Start` ``limits`` its tolerance and most iterations; its pressures and results into the
    :class:`Output` ``out``.  ``seen`` (max_iterations, n) booleans: room for the sets tried (any content)."""
    blocks, off, start, size, sym = layout.blocks, layout.off[j], layout.start, layout.size, layout.sym[j]
    h, w, at, load = cells.h[j], cells.w[j], cells.at[j], cells.load[j]
    tol, max_iterations = limits.tolerance, limits.max_iterations
    p, result = out.pressure[j], out.result[j]
    n = h.size
    nb = off.size
    built = layout.rows.built
    big = 0
    for b in range(nb):
        big = max(big, size[b])
    wk = Work(np.empty(big, dtype=np.int64), np.empty((big, 2)), np.empty((big, 2)), np.empty((big, big)))
    idx, rhs, sol = wk.idx, wk.rhs, wk.sol
    xh = np.zeros(n)
    xw = np.zeros(n)
    cp = np.zeros(n)
    g = np.zeros(n)
    single = False
    settled = False
    code = 1
    delta = 0.0
    it = 0
    for i in range(n):
        p[i] = 0.0
    for it in range(1, max_iterations + 1):
        singular = False
        for b in range(nb):
            o, s0, s = off[b], start[b], size[b]
            if it > 1:  # a block whose trial set is the last iteration's (seen[it - 2]) keeps its solution
                same = True
                for i in range(s0, s0 + s):
                    if seen[it - 2, i] != active[i]:
                        same = False
                        break
                if same:
                    continue
            m = np.int64(0)  # not the literal 0: numba compiled _factor_solve for Literal[int](0) as well
            for i in range(s):
                xh[s0 + i] = 0.0
                xw[s0 + i] = 0.0
                if active[s0 + i]:
                    if not built[j * nb + b, i]:
                        _row(blocks, o, layout.rows, j * nb + b, i)
                    idx[m] = i
                    rhs[m, 0] = h[s0 + i]
                    rhs[m, 1] = w[s0 + i]
                    m += 1
            if m == 0:
                continue
            if not _factor_solve(blocks, o, s, m, sym[b], wk):
                singular = True
                break
            for a in range(m):
                xh[s0 + idx[a]] = sol[a, 0]
                xw[s0 + idx[a]] = sol[a, 1]
        denom = 0.0
        num = 0.0
        for i in range(n):
            denom += at[i] * xw[i]
            num += at[i] * xh[i]
        if singular or not denom > 0.0:
            code = 3
            break
        delta = (load + num) / denom
        for i in range(n):
            p[i] = delta * xw[i] - xh[i] if active[i] else 0.0
        _matvec(layout, j, active, p, cp)
        d_scale = TINY
        p_scale = TINY
        for i in range(n):
            g[i] = h[i] - delta * w[i] + cp[i]
            d_scale = max(d_scale, abs(cp[i]))
            p_scale = max(p_scale, p[i])
        any_drop = False
        any_add = False
        for i in range(n):
            if active[i] and p[i] < 0.0:
                any_drop = True
            elif not active[i] and g[i] < -tol * d_scale:
                any_add = True
        if not any_drop and not any_add:
            settled = True
            break
        for r in range(it - 1):  # a set seen before: cycling, one cell per iteration from now on
            same = True
            for i in range(n):
                if seen[r, i] != active[i]:
                    same = False
                    break
            if same:
                single = True
                break
        for i in range(n):
            seen[it - 1, i] = active[i]
        if single:
            k = -1
            best = np.inf
            if any_drop:
                for i in range(n):
                    if active[i] and p[i] < 0.0 and p[i] / p_scale < best:
                        best = p[i] / p_scale
                        k = i
            else:
                for i in range(n):
                    if not active[i] and g[i] < -tol * d_scale and g[i] < best:
                        best = g[i]
                        k = i
            active[k] = not active[k]
        else:
            for i in range(n):
                if active[i]:
                    active[i] = not p[i] < 0.0
                else:
                    active[i] = g[i] < -tol * d_scale
        empty = True
        for i in range(n):
            if active[i]:
                empty = False
                break
        if empty:
            code = 4
            break
    # residuals, measured on the returned numbers
    for i in range(n):
        active[i] = p[i] > 0.0
    if not settled:  # settled: cp is already C[:, S] p_S of these pressures (the last set's cells of zero
        # pressure add only zeros to sums that start at +0.0: the same numbers to the last bit)
        _matvec(layout, j, active, p, cp)
    d_scale = TINY
    p_scale = TINY
    for i in range(n):
        d_scale = max(d_scale, abs(cp[i]))
        p_scale = max(p_scale, p[i])
    neg_p = -np.inf
    neg_g = -np.inf
    pg = -np.inf
    carried = 0.0
    for i in range(n):
        gi = h[i] - delta * w[i] + cp[i]
        neg_p = max(neg_p, -p[i])
        neg_g = max(neg_g, -gi)
        pg = max(pg, abs(p[i] * gi))
        carried += at[i] * p[i]
    comp = max(max(max(neg_p / p_scale, neg_g / d_scale), pg / (p_scale * d_scale)), 0.0)
    load_res = abs(carried - load) / load
    if settled:
        code = 0 if comp <= tol and load_res <= LOAD_TOL else 2
    result[0] = delta
    result[1] = it
    result[2] = code
    result[3] = comp
    result[4] = load_res


def solve_positions(layout, cells, limits, out):
    """:func:`active_set` of every problem j of the :class:`Layout` ``layout`` and the :class:`Cells`
    ``cells``, from the start sets and within the limits of the :class:`Start` ``limits``; into the
    :class:`Output` ``out``.  The one compiled entry of the contact solve."""
    blocks, off, start, size = layout.blocks, layout.off, layout.start, layout.size
    starts, given = limits.starts, limits.given
    N, n = cells.h.shape
    active = np.zeros(n, dtype=np.bool_)
    diag = np.empty(n)
    seen = np.empty((limits.max_iterations, n), dtype=np.bool_)
    for j in range(N):
        any_given = False
        if given[j]:
            for i in range(n):
                active[i] = starts[j, i]
                any_given = any_given or starts[j, i]
        if not any_given:
            for b in range(start.size):
                q = j * start.size + b
                if layout.rows.built[q, 0]:  # given whole (cycle.py's rows are made by the solve)
                    for i in range(size[b]):
                        diag[start[b] + i] = blocks[off[j, b] + i * size[b] + i]
                else:
                    _diagonal(layout.rows, q, diag[start[b]:start[b] + size[b]])
            initial_set(cells.h[j], cells.w[j], diag, cells.at[j], cells.load[j], active)
        active_set(layout, cells, j, limits, active, out, seen)


def kernels(solver=None):
    """The module of :func:`active_set` and :func:`solve_positions` on the solver's
    :attr:`~beveloid.solver.Solver.dense_backend`: its compiled twin
    (:func:`beveloid.solver.backends.compiled_module`) wherever numba is installed, whatever the
    solver's backend (as fe/principal.py's; why: :data:`beveloid.solver.DENSE_BACKEND_WHY`); this
    module itself without numba."""
    from ...solver import Solver, backends

    if Solver.of(solver).dense_backend == "numpy":
        return sys.modules[__name__]

    return backends.compiled_module(__name__, ("_row", "_diagonal", "_dot", "_factor_solve", "_matvec", "initial_set",
                                               "active_set", "solve_positions"))

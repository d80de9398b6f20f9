"""beveloid.ltca.mechanics.kernel: the contact solve making its blocks' rows from the pairs' tables as it reads
them (kernel.Rows, what the LTCA passes) gives the numbers of the same blocks given whole, bit for bit, on both
backends, and reads no row of a cell that never enters a trial set; its products C[:, S] p_S, a symmetric block's
summed by its active rows and another's by its rows over the active columns, are the dense products."""
from __future__ import annotations

import numpy as np
import pytest

from beveloid.ltca.mechanics import kernel
from beveloid.ltca.mechanics.halfspace import reduced_modulus_mpa, uniform_influence_blocks, uniform_influence_table

NX, NY = 5, 9
N = NX * NY
LOADED = np.array([[True, False, True], [True, True, False]])  # (J problems, P pairs)


def tables():
    J, P = LOADED.shape
    rng = np.random.default_rng(4)
    dx, dy = rng.uniform(0.05, 0.2, J * P), rng.uniform(0.3, 0.8, J * P)
    d = uniform_influence_table(dx, dy, NX, NY, reduced_modulus_mpa())
    lines = np.arange(NY)
    t = 2e-6 * np.exp(-np.abs(lines[:, None] - lines[None, :]) / 3.0)  # a symmetric tooth line compliance (mm/N)
    tooth = np.ascontiguousarray(np.broadcast_to(t, (J * P, NY, NY)) * rng.uniform(0.5, 2.0, J * P)[:, None, None])
    loaded = LOADED.reshape(-1)
    d[~loaded], tooth[~loaded] = 0.0, 0.0  # as cycle.compliance_tables gives a pair not in contact
    return d, tooth, dx * dy, loaded


def dense(d, tooth, area, loaded):
    """The blocks as the LTCA's compliance defines them (C[(i,a),(k,b)] = H + T[a, b] area), with numpy."""
    i, a = np.divmod(np.arange(N), NY)
    out = d[:, i[None, :] - i[:, None] + NX - 1, a[None, :] - a[:, None] + NY - 1] + tooth[:, a[:, None], a[None, :]] \
        * area[:, None, None]
    out[~loaded] = np.eye(N)
    return out


def problems():
    J, P = LOADED.shape
    x, y = np.divmod(np.arange(N), NY)
    bowl = ((x - NX // 2) * 0.1) ** 2 / 40 + ((y - NY // 2) * 0.5) ** 2 / 400
    h = np.where(LOADED[:, :, None], bowl[None, None] + np.arange(P)[None, :, None] * 2e-4, 10.0).reshape(J, P * N)
    return kernel.Cells(np.ascontiguousarray(h), np.ones((J, P * N)), np.full((J, P * N), 0.05),
                        np.array([40.0, 60.0]))


def solve(k, layout, start):
    J = LOADED.shape[0]
    out = kernel.Output(np.zeros((J, layout.start.size * N)), np.zeros((J, 5)))
    k.solve_positions(layout, problems(), kernel.Start(1e-10, 50, start, np.array([start.any()] * J)), out)
    return out


@pytest.mark.parametrize("name", ["numpy", "compiled"])
@pytest.mark.parametrize("warm", [False, True])
def test_rows_made_as_read_are_the_whole_blocks_numbers(name, warm):
    k = kernel if name == "numpy" else kernel.kernels()
    J, P = LOADED.shape
    d, tooth, area, loaded = tables()
    off = (np.arange(J * P, dtype=np.int64) * N * N).reshape(J, P)
    start, size, sym = np.arange(P, dtype=np.int64) * N, np.full(P, N, dtype=np.int64), np.ones((J, P), dtype=np.bool_)
    first = np.zeros((J, P * N), dtype=np.bool_)
    if warm:  # a start set given (the cell at each loaded grid's centre), else the uncoupled estimate
        for j, b in zip(*np.nonzero(LOADED)):
            first[j, b * N + N // 2] = True
    whole = solve(k, kernel.Layout(dense(d, tooth, area, loaded).reshape(-1), off, start, size, sym,
                                   kernel.given(J, size)), first if warm else first[:, :1])
    blocks = np.full(J * P * N * N, np.nan)  # a row the solve read without making it would spread nan
    rows = kernel.Rows(d, tooth, area, loaded, np.zeros((J * P, N), dtype=np.bool_))
    made = solve(k, kernel.Layout(blocks, off, start, size, sym, rows), first if warm else first[:, :1])
    assert np.all(whole.result[:, 2] == 0) and np.all(whole.result[:, 1] >= 2)  # converged, over several sets
    assert np.array_equal(made.pressure, whole.pressure) and np.array_equal(made.result, whole.result)
    contact = whole.pressure.reshape(J * P, N) > 0
    assert np.all(rows.built[contact]) and 0 < rows.built.sum() < 0.5 * rows.built[loaded].size  # only the rows read
    assert not rows.built[~loaded].any()
    assert np.isnan(blocks.reshape(J * P, N, N)[~rows.built]).all()


@pytest.mark.parametrize("name", ["numpy", "compiled"])
def test_products_over_the_active_cells_are_the_dense_products(name):
    k = kernel if name == "numpy" else kernel.kernels()
    rng = np.random.default_rng(7)
    sym = uniform_influence_blocks(0.1, 0.4, 5, 9, reduced_modulus_mpa())[0]  # symmetric to round-off
    sym = 0.5 * (sym + sym.T)
    other = sym + np.triu(rng.uniform(0.0, 0.2, sym.shape)) * sym.max()  # not symmetric
    blocks = [sym, other, sym[:20, :20].copy()]
    size = np.array([b.shape[0] for b in blocks], dtype=np.int64)
    start = np.concatenate([[0], np.cumsum(size)[:-1]]).astype(np.int64)
    off = np.concatenate([[0], np.cumsum(size * size)[:-1]]).astype(np.int64)
    flat = np.concatenate([b.ravel() for b in blocks])
    n = int(size.sum())
    active = rng.uniform(size=n) < 0.3
    p = np.where(active, rng.uniform(0.5, 2.0, n), 0.0)
    out = np.full(n, np.nan)
    layout = kernel.Layout(flat, off[None], start, size, np.array([[True, False, True]]), kernel.given(1, size))
    k._matvec(layout, 0, active, p, out)
    for b, s0, s in zip(blocks, start, size):
        cols = np.flatnonzero(active[s0:s0 + s])
        want = b[:, cols] @ p[s0 + cols]
        assert np.abs(out[s0:s0 + s] - want).max() <= 1e-13 * np.abs(want).max()

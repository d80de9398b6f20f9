"""beveloid.ltca.mechanics.kernel: the contact solve's products C[:, S] p_S, a symmetric block's summed by its
active rows and another's by its rows over the active columns, are the dense products, on both backends."""
from __future__ import annotations

import numpy as np
import pytest

from beveloid.ltca.mechanics import kernel
from beveloid.ltca.mechanics.halfspace import reduced_modulus_mpa, uniform_influence_blocks


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
    k._matvec(flat, off, start, size, np.array([True, False, True]), active, p, out)
    for b, s0, s in zip(blocks, start, size):
        cols = np.flatnonzero(active[s0:s0 + s])
        want = b[:, cols] @ p[s0 + cols]
        assert np.abs(out[s0:s0 + s] - want).max() <= 1e-13 * np.abs(want).max()

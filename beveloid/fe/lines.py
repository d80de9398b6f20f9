"""Flank points on the FE tooth's load grid: their four nodes and bilinear weights (:func:`corners`, W's
rows), and the compliance along lines of them, W C W^T (:func:`line_compliances`); plain Python in numba's
subset (compiled by :func:`beveloid.solver.backends.compiled_module`; interpreted where numba is absent).

A flank point's row of W holds four bilinear weights, at four load-grid nodes: the product W C W^T of a line of n points gathers those nodes' rows of C (4 n G
products) and then their 4 x 4 entries (4 n^2), against n G^2 + n^2 G for the dense product (G = 91
nodes, n = 11 to 17: 20 times fewer operations).  The same sums as the dense product's, in another
order: the same to round-off.
"""
from __future__ import annotations

import sys

import numpy as np


def _interp_index(x, xp):
    """numpy.interp(x, xp, arange(len(xp))) for xp[0] <= x <= xp[-1] (xp increasing), its arithmetic: the
    segment j with xp[j] <= x < xp[j + 1], slope 1 / (xp[j + 1] - xp[j]) times (x - xp[j]) plus j."""
    m = xp.shape[0]
    if x >= xp[m - 1]:
        return float(m - 1)
    lo, hi = 0, m - 1  # xp[lo] <= x < xp[hi]
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if xp[mid] <= x:
            lo = mid
        else:
            hi = mid
    slope = (float(lo + 1) - float(lo)) / (xp[lo + 1] - xp[lo])
    return slope * (x - xp[lo]) + float(lo)


def corners(p, radius, z, spare, nodes, w):
    """nodes (n, 4) and w (n, 4): the four load-grid nodes (profile-major) of each point p (n, 3) of a grid
    of node radii ``radius`` (ns, nz) at the axial positions ``z`` (nz,) and their bilinear weights; a point
    that is not finite gets zero weights, placed as the point ``spare`` (3,) (the numbers of
    :meth:`beveloid.fe.contact.FeTooth.corners`' numpy form, to the last bit)."""
    ns, nz = radius.shape
    for i in range(p.shape[0]):
        ok = True
        for k in range(3):
            if not np.isfinite(p[i, k]):
                ok = False
        x, y, zz = (p[i, 0], p[i, 1], p[i, 2]) if ok else (spare[0], spare[1], spare[2])
        zc = min(max(zz, z[0]), z[nz - 1])
        fz = _interp_index(zc, z)
        jz = min(int(fz), nz - 2)
        tz = fz - jz
        r = np.hypot(x, y)
        count = 0
        for s in range(ns):
            if (1 - tz) * radius[s, jz] + tz * radius[s, jz + 1] <= r:
                count += 1
        js = min(max(count - 1, 0), ns - 2)
        lo = (1 - tz) * radius[js, jz] + tz * radius[js, jz + 1]
        hi = (1 - tz) * radius[js + 1, jz] + tz * radius[js + 1, jz + 1]
        d, e = r - lo, hi - lo
        if e != 0.0:
            ts = d / e
        else:  # numpy's division by zero: inf of d's sign, NaN for 0 / 0
            ts = np.nan if d == 0.0 or not d == d else (np.inf if d > 0.0 else -np.inf)
        if ts < 0.0:  # numpy.clip's: a NaN stays NaN
            ts = 0.0
        elif ts > 1.0:
            ts = 1.0
        k = 0
        for da in range(2):
            wa = ts if da else 1 - ts
            for dz in range(2):
                nodes[i, k] = (js + da) * nz + jz + dz
                w[i, k] = wa * (tz if dz else 1 - tz) if ok else 0.0
                k += 1


def line_compliances(c, nodes, w, out):
    """out[q] = W_q C W_q^T (Q, n, n) for C ``c`` (G, G) and the lines' points' four load-grid ``nodes``
    (Q, n, 4) int64 with their weights ``w`` (Q, n, 4)."""
    Q, n = out.shape[0], out.shape[1]
    G = c.shape[0]
    wc = np.empty((n, G))
    for q in range(Q):
        for i in range(n):  # row i of W_q C
            for g in range(G):
                wc[i, g] = 0.0
            for a in range(4):
                wa = w[q, i, a]
                row = nodes[q, i, a]
                for g in range(G):
                    wc[i, g] += wa * c[row, g]
        for i in range(n):
            for j in range(n):
                v = 0.0
                for b in range(4):
                    v += wc[i, nodes[q, j, b]] * w[q, j, b]
                out[q, i, j] = v


def functions():
    """This module compiled when numba is installed (and not disabled), else itself."""
    from ..solver import backends

    if not backends.AVAILABLE:
        return sys.modules[__name__]
    return backends.compiled_module(__name__, ("_interp_index", "corners", "line_compliances"))

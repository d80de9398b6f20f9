"""Extreme principal stresses of the FE tooth's fillet nodes, plain Python in numba's subset (compiled
by :func:`beveloid.solver.backends.compiled_module`; interpreted where numba is absent).

The eigenvalues of a symmetric 3 x 3 tensor in closed form: the trigonometric solution of its
characteristic cubic (q the mean normal stress, p the deviator's norm / sqrt 6, phi from det of the
scaled deviator).  A fillet node is solved only where a bound of its Gershgorin bound (a diagonal
entry plus its row's off-diagonal magnitudes), linear in the node loads because they are >= 0, can
still reach the best value found: every other node cannot hold the extreme, so the answer is that
of solving every node.
"""
from __future__ import annotations

import math
import sys

import numpy as np

#: tensors are (..., 6): xx, yy, zz, xy, yz, zx
XX, YY, ZZ, XY, YZ, ZX = range(6)


def largest_eigenvalue(xx, yy, zz, xy, yz, zx):
    """The largest eigenvalue of the symmetric tensor (closed form)."""
    q = (xx + yy + zz) / 3.0
    a, b, c = xx - q, yy - q, zz - q
    p = math.sqrt((a * a + b * b + c * c + 2.0 * (xy * xy + yz * yz + zx * zx)) / 6.0)
    if not p > 0.0:
        return q
    det = (a * (b * c - yz * yz) - xy * (xy * c - yz * zx) + zx * (xy * yz - b * zx)) / (p * p * p)
    r = min(max(0.5 * det, -1.0), 1.0)
    return q + 2.0 * p * math.cos(math.acos(r) / 3.0)


def each_node(t, sign, out):
    """out[i] = sign x the largest eigenvalue of sign x t[i] (t (nf, 6)): the largest principal stress
    (sign +1) or the smallest (sign -1) of every node."""
    for i in range(t.shape[0]):
        out[i] = sign * largest_eigenvalue(sign * t[i, XX], sign * t[i, YY], sign * t[i, ZZ], sign * t[i, XY],
                                           sign * t[i, YZ], sign * t[i, ZX])


def bounds(op, sign):
    """(G, nc) per load column and node the largest over the rows r of sign a_rr + sum_c |a_rc| (op (nc,
    6, G) the nodes' stress per unit column load): with loads g >= 0, g @ bounds is at least every row's
    Gershgorin bound of sign x the node's tensor, so at least its largest eigenvalue."""
    nc, _, G = op.shape
    out = np.empty((G, nc))
    for i in range(nc):
        for c in range(G):
            axy, ayz, azx = abs(op[i, XY, c]), abs(op[i, YZ, c]), abs(op[i, ZX, c])
            out[c, i] = max(sign * op[i, XX, c] + axy + azx, sign * op[i, YY, c] + axy + ayz,
                            sign * op[i, ZZ, c] + azx + ayz)
    return out


def _exact(op, i, g, q, cols, m, sign, t):
    for r in range(6):
        t[r] = 0.0
    for a in range(m):
        c = cols[a]
        for r in range(6):
            t[r] += op[i, r, c] * g[q, c]
    return largest_eigenvalue(sign * t[XX], sign * t[YY], sign * t[ZZ], sign * t[XY], sign * t[YZ], sign * t[ZX])


def extreme(op, bound, near, g, sign, node, value):
    """For each load set q of g (Q, G) (node loads >= 0): the node of op (nc, 6, G) (bound: :func:`bounds`) with the largest
    principal stress (sign +1) or the smallest (sign -1), into node[q], value[q] (the lowest node among
    equal values), among the nodes not ``near`` (G, nc, non-zero: within the reading depth) a column
    the set loads; node -1 and value NaN where every node is near a loaded column.  The tensors are
    summed over the set's non-zero loads only; a node is solved only where its bound (:func:`bounds` @
    g) can still reach the best value found, starting from the node of the largest bound: every other
    node cannot hold the extreme (module docstring)."""
    Q, G = g.shape
    nc = op.shape[0]
    cols = np.empty(G, dtype=np.int64)
    b = np.empty(nc)
    skip = np.empty(nc, dtype=np.bool_)
    t = np.empty(6)
    for q in range(Q):
        m = 0
        for c in range(G):
            if g[q, c] != 0.0:
                cols[m] = c
                m += 1
        for i in range(nc):
            b[i] = 0.0
            skip[i] = False
        for a in range(m):
            c = cols[a]
            w = g[q, c]
            for i in range(nc):
                b[i] += bound[c, i] * w
                if near[c, i] != 0:
                    skip[i] = True
        k = -1
        for i in range(nc):
            if not skip[i] and (k < 0 or b[i] > b[k]):
                k = i
        if k < 0:
            node[q] = -1
            value[q] = np.nan
            continue
        best = _exact(op, k, g, q, cols, m, sign, t)
        for i in range(nc):
            if i == k or skip[i] or b[i] < best:
                continue
            v = _exact(op, i, g, q, cols, m, sign, t)
            if v > best or (v == best and i < k):
                best = v
                k = i
        node[q] = k
        value[q] = sign * best


def functions():
    """This module compiled when numba is installed (and not disabled), else itself."""
    from ..solver import backends

    if not backends.AVAILABLE:
        return sys.modules[__name__]
    return backends.compiled_module(__name__, ("largest_eigenvalue", "each_node", "bounds", "_exact", "extreme"))

"""Extreme principal stresses of the FE tooth's fillet nodes, plain Python in numba's subset (compiled
by :func:`beveloid.solver.backends.compiled_module`; interpreted where numba is absent).

The eigenvalues of a symmetric 3 x 3 tensor in closed form: the trigonometric solution of its
characteristic cubic (q the mean normal stress, p the deviator's norm / sqrt 6, phi from det of the
scaled deviator).  A fillet node is solved only where its Gershgorin bound (a diagonal entry plus its
row's off-diagonal magnitudes) can still beat the best value found: every other node cannot hold the
extreme, so the answer is that of solving every node.
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


def extreme(t, sign, node, value):
    """For each load set q of t (Q, nf, 6): the node with the largest principal stress (sign +1) or the
    smallest (sign -1), into node[q], value[q] (module docstring)."""
    Q, nf = t.shape[0], t.shape[1]
    for q in range(Q):
        low = -np.inf  # the best diagonal entry: the extreme is at least this
        for i in range(nf):
            low = max(low, sign * t[q, i, XX], sign * t[q, i, YY], sign * t[q, i, ZZ])
        best = -np.inf
        k = -1
        for i in range(nf):
            xx, yy, zz = sign * t[q, i, XX], sign * t[q, i, YY], sign * t[q, i, ZZ]
            axy, ayz, azx = abs(t[q, i, XY]), abs(t[q, i, YZ]), abs(t[q, i, ZX])
            high = max(xx + axy + azx, yy + axy + ayz, zz + azx + ayz)
            if high < low or high <= best:
                continue
            v = largest_eigenvalue(xx, yy, zz, sign * t[q, i, XY], sign * t[q, i, YZ], sign * t[q, i, ZX])
            if v > best:
                best = v
                k = i
        node[q] = k
        value[q] = sign * best


def functions():
    """This module compiled when numba is installed (and not disabled), else itself."""
    from ..solver import backends

    if not backends.AVAILABLE:
        return sys.modules[__name__]
    return backends.compiled_module(__name__, ("largest_eigenvalue", "each_node", "extreme"))

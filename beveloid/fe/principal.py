"""Extreme principal stresses of the FE tooth's fillet nodes, plain Python in numba's subset (compiled
by :func:`beveloid.solver.backends.compiled_module`; interpreted where numba is absent).

The eigenvalues of a symmetric 3 x 3 tensor in closed form: the trigonometric solution of its
characteristic cubic (q the mean normal stress, p the deviator's norm / sqrt 6, phi from det of the
scaled deviator).  The largest eigenvalue is convex and positively homogeneous, so under node loads g
>= 0 a node's is at most sum_c g_c lambda_c, lambda_c that of its stress under a unit load on column c
alone (:func:`bounds`, with a margin above the closed form's rounding).  A fillet node is solved only
where that bound can still reach the best value found, and a block of nodes only where the largest of
its nodes' bounds can (:func:`block_bounds`, the nodes in blocks of neighbours): every other node
cannot hold the extreme, so the answer is that of solving every node.
"""
from __future__ import annotations

import math
import sys
import typing

import numpy as np

#: tensors are (..., 6): xx, yy, zz, xy, yz, zx
XX, YY, ZZ, XY, YZ, ZX = range(6)


class Fillet(typing.NamedTuple):
    """One fillet's nodes as :func:`extreme` reads them."""

    op: np.ndarray  # (nc, 6, G) the nodes' stress tensors per unit load on each load-grid column
    bound: np.ndarray  # (G, nc) :func:`bounds` of op, for its sign
    top: np.ndarray  # (G, nb) :func:`block_bounds` of bound
    order: np.ndarray  # (nc,) int64: the nodes, neighbours together; block b is order[b size:(b + 1) size]
    size: int  # nodes per block
    near: np.ndarray  # (G, nc) uint8: node within the reading depth of the column


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


def _loaded_columns(g, q, cols):
    """The number m of non-zero loads of set q of g (Q, G), their columns in cols[:m]."""
    m = 0
    for c in range(g.shape[1]):
        if g[q, c] != 0.0:
            cols[m] = c
            m += 1
    return m


def slice_extremes(fillet, g, q, sign, counted, slot, out):
    """out[s] = sign x the largest eigenvalue of sign x the tensor, over the ``counted`` nodes i of the
    :class:`Fillet` in slice ``slot[i]`` = s, under load set q of g (Q, G) (NaN for a slice without one): the
    largest principal stress (sign +1) or the smallest (sign -1) of every slice, each tensor summed over
    the set's non-zero loads as :func:`extreme` sums it, a node solved only where its bound (:func:`bounds`)
    can still reach its slice's best value (first the node of the slice's largest bound)."""
    op, bound = fillet.op, fillet.bound
    nc = op.shape[0]
    cols = np.empty(g.shape[1], dtype=np.int64)
    m = _loaded_columns(g, q, cols)
    b = np.zeros(nc)
    for a in range(m):
        c = cols[a]
        w = g[q, c]
        for i in range(nc):
            b[i] += bound[c, i] * w
    top = np.full(out.shape[0], -1, dtype=np.int64)
    for i in range(nc):
        s = slot[i]
        if counted[i] and (top[s] < 0 or b[i] > b[top[s]]):
            top[s] = i
    t = np.empty(6)
    best = np.full(out.shape[0], -np.inf)
    for s in range(out.shape[0]):
        if top[s] >= 0:
            best[s] = _exact(op, top[s], g, q, cols, m, sign, t)
    for i in range(nc):
        s = slot[i]
        if counted[i] and i != top[s] and b[i] >= best[s]:
            v = _exact(op, i, g, q, cols, m, sign, t)
            if v > best[s]:
                best[s] = v
    for s in range(out.shape[0]):
        out[s] = sign * best[s] if top[s] >= 0 else np.nan


#: the bound's margin, times the largest stress magnitude of a node's unit-load tensor: far above the
#: rounding of the closed form and of a sum of tensors, so that no node holding the extreme is skipped
BOUND_MARGIN = 1e-6


def bounds(op, sign):
    """(G, nc) per load column c and node i: lambda_c, the largest eigenvalue of sign x the node's tensor
    under a unit load on c alone (op (nc, 6, G) the nodes' stress per unit column load), plus
    :data:`BOUND_MARGIN` times its largest entry's magnitude: with loads g >= 0, g @ bounds is at least
    the largest eigenvalue of sign x the node's tensor (module docstring)."""
    nc, _, G = op.shape
    out = np.empty((G, nc))
    for i in range(nc):
        for c in range(G):
            scale = 0.0
            for r in range(6):
                scale = max(scale, abs(op[i, r, c]))
            out[c, i] = largest_eigenvalue(sign * op[i, XX, c], sign * op[i, YY, c], sign * op[i, ZZ, c],
                                           sign * op[i, XY, c], sign * op[i, YZ, c], sign * op[i, ZX, c]) \
                + BOUND_MARGIN * scale
    return out


def block_bounds(bound, order, size):
    """(G, nb) per load column the largest bound (:func:`bounds`) of each block of ``size`` nodes, the
    nodes taken in ``order`` (neighbours together: a block's bound is then close to its nodes')."""
    G, nc = bound.shape
    nb = (nc + size - 1) // size
    out = np.full((G, nb), -np.inf)
    for s in range(nc):
        i = order[s]
        for c in range(G):
            out[c, s // size] = max(out[c, s // size], bound[c, i])
    return out


def _exact(op, i, g, q, cols, m, sign, t):
    for r in range(6):
        t[r] = 0.0
    for a in range(m):
        c = cols[a]
        for r in range(6):
            t[r] += op[i, r, c] * g[q, c]
    return largest_eigenvalue(sign * t[XX], sign * t[YY], sign * t[ZZ], sign * t[XY], sign * t[YZ], sign * t[ZX])


def extreme(fillet, g, sign, node, value):
    """For each load set q of g (Q, G) (node loads >= 0): the node of the :class:`Fillet` with the largest
    principal stress (sign +1) or the smallest (sign -1), into node[q], value[q] (the lowest node among
    equal values), among the nodes not ``near`` (G, nc, non-zero: within the reading depth) a column
    the set loads; node -1 and value NaN where every node is near a loaded column.  The tensors are
    summed over the set's non-zero loads only.  The blocks are visited by their bound @ g, largest
    first (the largest left picked at each step), until one cannot reach the best value found; in a block a node is solved only where its
    bound (:func:`bounds` @ g) can: every other node cannot hold the extreme (module docstring)."""
    op, bound, top, order, size, near = fillet
    Q, G = g.shape
    nc = op.shape[0]
    nb = top.shape[1]
    cols = np.empty(G, dtype=np.int64)
    bb = np.empty(nb)
    t = np.empty(6)
    for q in range(Q):
        m = _loaded_columns(g, q, cols)
        for blk in range(nb):
            bb[blk] = 0.0
        for a in range(m):
            c = cols[a]
            w = g[q, c]
            for blk in range(nb):
                bb[blk] += top[c, blk] * w
        k = -1
        best = -np.inf
        for r in range(nb):
            # the block of the largest bound not yet visited (a few of the blocks are visited: no sort of all)
            blk = -1
            for c in range(nb):
                if blk < 0 or bb[c] > bb[blk]:
                    blk = c
            if bb[blk] == -np.inf or (k >= 0 and bb[blk] < best):
                break
            bb[blk] = -np.inf  # visited
            for s in range(blk * size, min(nc, (blk + 1) * size)):
                i = order[s]
                b = 0.0
                skip = False
                for a in range(m):
                    c = cols[a]
                    if near[c, i] != 0:
                        skip = True
                        break
                    b += bound[c, i] * g[q, c]
                if skip or (k >= 0 and b < best):
                    continue
                v = _exact(op, i, g, q, cols, m, sign, t)
                if k < 0 or v > best or (v == best and i < k):
                    best = v
                    k = i
        if k < 0:
            node[q] = -1
            value[q] = np.nan
        else:
            node[q] = k
            value[q] = sign * best


def fillet(op, sign, order, size, near) -> Fillet:
    """The :class:`Fillet` of the stress operator ``op`` (nc, 6, G), C-contiguous, for ``sign``: its
    :func:`bounds` and :func:`block_bounds` (blocks of ``size`` nodes taken in ``order``, int64)."""
    fn = functions()
    bound = fn.bounds(op, sign)
    return Fillet(op, bound, fn.block_bounds(bound, order, size), order, size, near)


def compile_now() -> None:
    """Every compiled function (and fe/lines.py's) made ready now (compiled, or loaded from numba's cache) by a fillet of two
    nodes under three load columns, passed as the FE tooth passes its own (beveloid/fe/contact.py): the
    same argument types, so that its root stresses compile nothing more.  ``beveloid paper`` calls it on
    a worker at the start, before the FE teeth exist, so that its loaded pieces do not compile these
    functions each at the same time."""
    fn = functions()
    op = np.zeros((2, 6, 3))
    op[:, XX, :] = 1.0
    f = fillet(op, 1.0, np.arange(2, dtype=np.int64), 2, np.zeros((3, 2), dtype=np.uint8))
    g = np.ones((1, 3))
    fn.extreme(f, g, 1.0, np.zeros(1, dtype=np.int64), np.full(1, np.nan))
    fn.slice_extremes(f, g, 0, 1.0, np.ones(2, dtype=bool), np.zeros(2, dtype=np.int64), np.empty(1))
    from . import lines  # the FE tooth's line compliances (FeTooth.line_compliances), compiled with them

    lines.functions().line_compliances(np.eye(3), np.zeros((1, 2, 4), dtype=np.int64), np.ones((1, 2, 4)),
                                       np.empty((1, 2, 2)))
    lines.functions().corners(np.zeros((1, 3)), np.array([[1.0, 1.0], [2.0, 2.0]]), np.arange(2.0), np.zeros(3),
                              np.empty((1, 4), dtype=np.int64), np.empty((1, 4)))


def functions():
    """This module compiled when numba is installed (and not disabled), else itself."""
    from ..solver import backends

    if not backends.AVAILABLE:
        return sys.modules[__name__]
    return backends.compiled_module(__name__, ("largest_eigenvalue", "_loaded_columns", "slice_extremes", "bounds",
                                               "block_bounds", "_exact", "extreme"))

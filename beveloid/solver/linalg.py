"""Small dense linear algebra of the solver core (no allocation; numba subset).

Plain Python in numba's subset: compiled with the rest of the core by
:mod:`beveloid.solver.backends` (see :mod:`beveloid.solver.core`)."""
import math


from ..generated.tca_kernels_scalar import N_UNKNOWNS

def copy_into(dst, src):
    """dst[:] = src for vectors, in the subset numba compiles without reference counting (and
    without numba's shape check of a slice assignment, whose error message alone cost ~2 s of the
    first compilation: docs/performance.md)."""
    for i in range(src.shape[0]):
        dst[i] = src[i]


def copy_matrix_into(dst, src):
    """dst[:, :] = src, as :func:`copy_into`."""
    for i in range(src.shape[0]):
        for j in range(src.shape[1]):
            dst[i, j] = src[i, j]


def solve_linear(A, b, out):
    """out = A^-1 b for the N_UNKNOWNS x N_UNKNOWNS system (A, b copied) by partial pivoting; False
    if A is singular or not finite.  (n is a compile-time constant for numba.)"""
    n = N_UNKNOWNS
    M = A.copy()
    v = b.copy()
    for c in range(n):
        piv = c
        big = abs(M[c, c])
        for r in range(c + 1, n):
            if abs(M[r, c]) > big:
                big = abs(M[r, c])
                piv = r
        if big == 0.0 or not math.isfinite(big):
            return False
        if piv != c:
            for k in range(n):
                t = M[c, k]
                M[c, k] = M[piv, k]
                M[piv, k] = t
            t = v[c]
            v[c] = v[piv]
            v[piv] = t
        for r in range(c + 1, n):
            f = M[r, c] / M[c, c]
            if f != 0.0:
                for k in range(c, n):
                    M[r, k] -= f * M[c, k]
                v[r] -= f * v[c]
    for c in range(n - 1, -1, -1):
        s = v[c]
        for k in range(c + 1, n):
            s -= M[c, k] * out[k]
        out[c] = s / M[c, c]
    return True


def residual_norm(F, scale, n_mm=3):
    """max |F_i| in mm: rows from n_mm on (normals, tangency: dimensionless) times the length scale;
    inf if not finite."""
    r = 0.0
    for i in range(F.shape[0]):
        v = abs(F[i]) * (scale if i >= n_mm else 1.0)
        if not math.isfinite(v):
            return math.inf
        if v > r:
            r = v
    return r

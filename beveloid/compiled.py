"""Compiled TCA path: the generated scalar kernels (generated/*_scalar.py) under numba.

The scalar kernels come from the same CSE pass and templates as the numpy kernels; this
module only adds the loops: a 5x5 Newton with partial-pivot elimination, tangent
continuation along the pinion angle, the error homotopy and the flank-boundary checks, one
error set per thread (``prange``).  numba is optional: ``AVAILABLE`` is False without it and
the numpy path in :mod:`beveloid.tca` / :mod:`beveloid.sweep` is used instead.
"""
from __future__ import annotations

import math

import numpy as np

try:  # optional dependency
    import numba

    AVAILABLE = True
except ImportError:  # pragma: no cover - exercised by the numpy-only tests
    numba = None
    AVAILABLE = False

if AVAILABLE:
    from .generated import tca_system_scalar as _ts
    from .generated import tooth_surface_scalar as _ss

    _jit = numba.njit(cache=True, nogil=True, fastmath=False)
    _res_left = _jit(_ts.residual_left_point)
    _res_right = _jit(_ts.residual_right_point)
    _surf_left = _jit(_ss.surface_left_point)
    _surf_right = _jit(_ss.surface_right_point)

    @_jit
    def _residual(flank, x, phi1, e, p, F, J, Je, Jp):
        if flank == 0:
            _res_left(x[0], x[1], x[2], x[3], x[4], phi1, e[0], e[1], e[2], e[3], e[4],
                      p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], p[8], p[9], p[10], p[11], p[12], p[13],
                      p[14], p[15], F, J, Je, Jp)
        else:
            _res_right(x[0], x[1], x[2], x[3], x[4], phi1, e[0], e[1], e[2], e[3], e[4],
                       p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], p[8], p[9], p[10], p[11], p[12], p[13],
                       p[14], p[15], F, J, Je, Jp)

    @_jit
    def _solve(A, b, out):
        """out = A^-1 b for 5x5 A (copied), partial pivoting; returns False if singular."""
        M = A.copy()
        v = b.copy()
        n = 5
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
                    M[c, k], M[piv, k] = M[piv, k], M[c, k]
                v[c], v[piv] = v[piv], v[c]
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

    @_jit
    def _newton(flank, x, phi1, e, p, scale, tol, max_iter, F, J, Je, Jp, step):
        """In place on x. Returns (converged, iterations); F, J, Je, Jp hold the last evaluation."""
        for it in range(max_iter + 1):
            _residual(flank, x, phi1, e, p, F, J, Je, Jp)
            r = 0.0
            for i in range(5):
                v = abs(F[i]) * (scale if i >= 3 else 1.0)
                if not math.isfinite(v):
                    return False, it
                if v > r:
                    r = v
            if r <= tol:
                return True, it
            if it == max_iter:
                break
            for i in range(5):
                F[i] = -F[i]
            if not _solve(J, F, step):
                return False, it
            for i in range(5):
                x[i] += step[i]
        return False, max_iter

    @_jit
    def _margin(flank, x, p, lim, pt, nr, ph):
        """Smallest signed distance (mm) inside the flank boundaries of both members.

        lim rows (pinion, gear): r, tip height + shift, cos(cone), tan(cone), z_lo, z_hi, rack params...
        pt, nr (3,) and ph (1,) are scratch arrays for the surface kernel.
        """
        best = 1e300
        for m in range(2):
            l = x[0] if m == 0 else x[2]
            u = x[1] if m == 0 else x[3]
            # surface params: alpha_n, helix, cone, cutter addendum, b, shift, pitch radius
            if flank == 0:
                _surf_left(l, u, p[0], lim[m, 6], lim[m, 7], lim[m, 8], p[1], lim[m, 9], lim[m, 0], pt, nr, ph)
            else:
                _surf_right(l, u, p[0], lim[m, 6], lim[m, 7], lim[m, 8], p[1], lim[m, 9], lim[m, 0], pt, nr, ph)
            rad = math.sqrt(pt[0] * pt[0] + pt[1] * pt[1])
            tip = lim[m, 0] + lim[m, 1] / lim[m, 2] + pt[2] * lim[m, 3]
            for v in (l, tip - rad, pt[2] - lim[m, 4], lim[m, 5] - pt[2]):
                if v < best:
                    best = v
        return best

    @_jit
    def _tangent(J, Jp, dx):
        neg = np.empty(5)
        for i in range(5):
            neg[i] = -Jp[i]
        return _solve(J, neg, dx)

    @numba.njit(cache=True, parallel=True)
    def sweep_paths(flank, x_ref, phi_ref, errors, phi_grid, p, lim, scale, tol, max_iter, homotopy_steps,
                    edge_tol, x_out, code_out, iters_out):
        """Error sets (K, 5) x pinion angles (N,): contact unknowns, status codes and iterations.

        x_ref: aligned pitch-point solution at phi_ref.  phi_grid must be sorted ascending.
        Status codes: 0 ok, 1 edge, 2 outside, 3 failed.
        """
        K = errors.shape[0]
        N = phi_grid.shape[0]
        # first grid index at or above phi_ref
        j0 = 0
        while j0 < N and phi_grid[j0] < phi_ref:
            j0 += 1
        for k in numba.prange(K):
            F = np.empty(5)
            J = np.empty((5, 5))
            Je = np.empty((5, 5))
            Jp = np.empty(5)
            step = np.empty(5)
            dx = np.empty(5)
            e = np.zeros(5)
            de = np.empty(5)
            rhs = np.empty(5)
            pt = np.empty(3)
            nr = np.empty(3)
            ph = np.empty(1)
            x = x_ref.copy()
            ok_all = True
            # homotopy in the errors at phi_ref (tangent predictor from d/derrors)
            for h in range(1, homotopy_steps + 1):
                _residual(flank, x, phi_ref, e, p, F, J, Je, Jp)
                for i in range(5):
                    de[i] = errors[k, i] * (1.0 / homotopy_steps)
                for i in range(5):
                    s = 0.0
                    for c in range(5):
                        s -= Je[i, c] * de[c]
                    rhs[i] = s
                if _solve(J, rhs, dx):
                    for i in range(5):
                        x[i] += dx[i]
                for i in range(5):
                    e[i] = errors[k, i] * h / homotopy_steps
                conv, _ = _newton(flank, x, phi_ref, e, p, scale, tol, max_iter, F, J, Je, Jp, step)
                ok_all = ok_all and conv
            xs = x.copy()
            Jst = J.copy()
            Jpst = Jp.copy()
            # march up then down from phi_ref with a tangent predictor
            for direction in range(2):
                x[:] = xs
                J[:, :] = Jst
                Jp[:] = Jpst
                prev = phi_ref
                good = ok_all
                if direction == 0:
                    rng_lo, rng_hi, inc = j0, N, 1
                else:
                    rng_lo, rng_hi, inc = j0 - 1, -1, -1
                j = rng_lo
                while j != rng_hi:
                    phi = phi_grid[j]
                    if good and _tangent(J, Jp, dx):
                        for i in range(5):
                            x[i] += dx[i] * (phi - prev)
                    conv, it = _newton(flank, x, phi, errors[k], p, scale, tol, max_iter, F, J, Je, Jp, step)
                    for i in range(5):
                        x_out[k, j, i] = x[i]
                    iters_out[k, j] = it
                    if conv and ok_all:
                        m = _margin(flank, x, p, lim, pt, nr, ph)
                        if m > edge_tol:
                            code_out[k, j] = 0
                        elif m >= -edge_tol:
                            code_out[k, j] = 1
                        else:
                            code_out[k, j] = 2
                    else:
                        code_out[k, j] = 3
                        x[:] = xs  # restart the next point from the reference
                    good = conv
                    prev = phi
                    j += inc

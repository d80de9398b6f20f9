"""The contact solver, written once: Newton on Eq 38, error homotopy, path continuation and
classification.

Every function here is plain Python over floats and small numpy arrays, in the subset that
numba compiles.  :mod:`beveloid.solver.backends` runs the same functions either as they are
("numpy" backend, the reference) or compiled by numba ("compiled" backend).  They reach the
maths only through the generated glue ``tca_kernels_scalar`` (the Eq 38 system of the two
members' surface models and the flank margins), so a new surface model changes nothing here.

A *problem* is the tuple (pinion_model, gear_model, flank, pinion_params, gear_params, pair)
of model and flank indices and the generated parameter vectors (see beveloid/tca.py).
"""
import math

import numpy as np

from ..generated.tca_kernels_scalar import N_ERRORS, N_UNKNOWNS, contact_margin_point, contact_system_point, workspace
from ..status import Status

try:
    from numba import prange
except ImportError:  # pragma: no cover - numba-free installs
    prange = range

OK = int(Status.OK)
EDGE = int(Status.EDGE)
OUTSIDE = int(Status.OUTSIDE)
FAILED = int(Status.FAILED)

#: Functions compiled with numba's parallel=True by the compiled backend.
PARALLEL = ("solve_paths",)


def scratch():
    """Work arrays of one solver thread: (workspace, F, J, Je, Jp, step, dx, rhs, e)."""
    return (workspace(), np.empty(N_UNKNOWNS), np.empty((N_UNKNOWNS, N_UNKNOWNS)),
            np.empty((N_UNKNOWNS, N_ERRORS)), np.empty(N_UNKNOWNS), np.empty(N_UNKNOWNS), np.empty(N_UNKNOWNS),
            np.empty(N_UNKNOWNS), np.empty(N_ERRORS))


def evaluate(problem, x, phi1, e, ws, F, J, Je, Jp):
    """Eq 38 at unknowns x: residual F, d/d unknowns J, d/d errors Je, d/d pinion angle Jp."""
    pinion_model, gear_model, flank, pinion_params, gear_params, pair = problem
    contact_system_point(pinion_model, gear_model, flank, x, phi1, e, pinion_params, gear_params, pair, ws, F, J, Je,
                         Jp)


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


def residual_norm(F, scale):
    """max |F_i| in mm: the normal rows (dimensionless) times the length scale; inf if not finite."""
    r = 0.0
    for i in range(F.shape[0]):
        v = abs(F[i]) * (scale if i >= 3 else 1.0)
        if not math.isfinite(v):
            return math.inf
        if v > r:
            r = v
    return r


def newton(problem, x, phi1, e, scale, tol, max_iter, ws, F, J, Je, Jp, step):
    """Newton in place on x.  Returns (converged, iterations); F, J, Je, Jp and ws hold the
    last evaluation (at the returned x)."""
    for it in range(max_iter + 1):
        evaluate(problem, x, phi1, e, ws, F, J, Je, Jp)
        r = residual_norm(F, scale)
        if not math.isfinite(r):
            return False, it
        if r <= tol:
            return True, it
        if it == max_iter:
            break
        for i in range(F.shape[0]):
            F[i] = -F[i]
        if not solve_linear(J, F, step):
            return False, it
        for i in range(x.shape[0]):
            x[i] += step[i]
    return False, max_iter


def classify(converged, margin, edge_tol):
    """Status code of a point from convergence and its smallest flank margin (mm)."""
    if not converged or not math.isfinite(margin):
        return FAILED
    if margin > edge_tol:
        return OK
    if margin >= -edge_tol:
        return EDGE
    return OUTSIDE


def homotopy(problem, x, phi_ref, target, steps, scale, tol, max_iter, ws, F, J, Je, Jp, step, dx, e, rhs):
    """Carry the solution x at phi_ref from zero errors to ``target`` in ``steps`` equal steps,
    each predicted along d x / d errors and corrected by Newton.  In place; True if every step
    converged.  On return e == target."""
    ok = True
    for i in range(e.shape[0]):
        e[i] = 0.0
    for h in range(1, steps + 1):
        evaluate(problem, x, phi_ref, e, ws, F, J, Je, Jp)
        for i in range(rhs.shape[0]):
            s = 0.0
            for c in range(e.shape[0]):
                s -= Je[i, c] * target[c] / steps
            rhs[i] = s
        if solve_linear(J, rhs, dx):
            for i in range(x.shape[0]):
                x[i] += dx[i]
        for c in range(e.shape[0]):
            e[c] = target[c] if h == steps else target[c] * h / steps
        conv, _ = newton(problem, x, phi_ref, e, scale, tol, max_iter, ws, F, J, Je, Jp, step)
        ok = ok and conv
    return ok


def solve_paths(problem, pinion_blank, gear_blank, x_ref, phi_ref, errors, phi_grid, scale, tol, max_iter,
                homotopy_steps, edge_tol, x_out, code_out, iters_out, boundary_out):
    """Error sets (K, N_ERRORS) x pinion angles (N,) sorted ascending: contact unknowns, status
    codes, Newton iterations and the index of the nearest flank boundary (-1 if failed).

    x_ref is the aligned contact at phi_ref.  Per error set: the homotopy in the errors at
    phi_ref, then a march up and a march down the grid with the exact tangent d x / d phi_1 as
    predictor, plus the second-order term from the change of the tangent over the last step once
    two converged points are behind (non-conjugate surfaces, e.g. crowned: one Newton step instead
    of two).  A point that fails restarts the next one from the homotopy's solution.
    """
    K = errors.shape[0]
    N = phi_grid.shape[0]
    j0 = 0
    while j0 < N and phi_grid[j0] < phi_ref:
        j0 += 1
    for k in prange(K):
        ws, F, J, Je, Jp, step, dx, rhs, e = scratch()
        x = x_ref.copy()
        ok_all = homotopy(problem, x, phi_ref, errors[k], homotopy_steps, scale, tol, max_iter, ws, F, J, Je, Jp,
                          step, dx, e, rhs)
        xs = x.copy()
        Jst = J.copy()
        Jpst = Jp.copy()
        tprev = np.empty(N_UNKNOWNS)  # tangent at the previous converged point
        for direction in range(2):
            x[:] = xs
            J[:, :] = Jst
            Jp[:] = Jpst
            prev = phi_ref
            good = ok_all
            curved = False  # tprev and hprev hold the last step's tangent and length
            hprev = 0.0
            if direction == 0:
                j, stop, inc = j0, N, 1
            else:
                j, stop, inc = j0 - 1, -1, -1
            while j != stop:
                phi = phi_grid[j]
                h = phi - prev
                predicted = False
                if good:
                    for i in range(N_UNKNOWNS):
                        rhs[i] = -Jp[i]
                    if solve_linear(J, rhs, dx):
                        predicted = True
                        for i in range(N_UNKNOWNS):
                            x[i] += dx[i] * h
                            if curved and hprev != 0.0:
                                x[i] += 0.5 * (dx[i] - tprev[i]) / hprev * h * h
                conv, it = newton(problem, x, phi, e, scale, tol, max_iter, ws, F, J, Je, Jp, step)
                curved = conv and predicted
                if curved:
                    tprev[:] = dx
                    hprev = h
                for i in range(N_UNKNOWNS):
                    x_out[k, j, i] = x[i]
                iters_out[k, j] = it
                if conv and ok_all:
                    margin, which = contact_margin_point(x, pinion_blank, gear_blank, ws)
                    code_out[k, j] = classify(True, margin, edge_tol)
                    boundary_out[k, j] = which
                else:
                    code_out[k, j] = FAILED
                    boundary_out[k, j] = -1
                    x[:] = xs  # restart the next point from the reference
                good = conv
                prev = phi
                j += inc


def solve_point(problem, x, phi1, errors, scale, tol, max_iter):
    """One Newton solve from the guess x (copied): (x, converged, iterations, residual_norm_mm)."""
    ws, F, J, Je, Jp, step, _, _, _ = scratch()
    xs = x.copy()
    conv, it = newton(problem, xs, phi1, errors, scale, tol, max_iter, ws, F, J, Je, Jp, step)
    return xs, conv, it, residual_norm(F, scale)

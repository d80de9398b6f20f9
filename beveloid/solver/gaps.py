"""Normal gaps of the loaded TCA: from a point on one flank along its normal to the mating flank.

Plain Python in numba's subset: compiled with the rest of the core by
:mod:`beveloid.solver.backends` (see :mod:`beveloid.solver.core`)."""
import math

import numpy as np

from ..generated.tca_kernels import UNKNOWNS
from ..generated.tca_kernels_scalar import N_ERRORS, N_UNKNOWNS, contact_margin_point, surface_jet_point
from .newton import GEAR_ANGLE, evaluate, scratch

#: where normal_gaps finds each unknown (by the generated names; numba reads them as constants)
PINION_L = UNKNOWNS.index("pinion_l_mm")
PINION_U = UNKNOWNS.index("pinion_u_mm")
GEAR_L = UNKNOWNS.index("gear_l_mm")
GEAR_U = UNKNOWNS.index("gear_u_mm")


def _solve3(a00, a01, a02, a10, a11, a12, a20, a21, a22, b0, b1, b2, out):
    """out = A^-1 b for a 3x3 system by Cramer's rule; False if A is singular or not finite."""
    c00 = a11 * a22 - a12 * a21
    c01 = a12 * a20 - a10 * a22
    c02 = a10 * a21 - a11 * a20
    det = a00 * c00 + a01 * c01 + a02 * c02
    if det == 0.0 or not math.isfinite(det):
        return False
    out[0] = (b0 * c00 + a01 * (b2 * a12 - b1 * a22) + a02 * (b1 * a21 - b2 * a11)) / det
    out[1] = (a00 * (b1 * a22 - b2 * a12) + b0 * c01 + a02 * (b2 * a10 - b1 * a20)) / det
    out[2] = (a00 * (a11 * b2 - a21 * b1) + a01 * (a20 * b1 - a10 * b2) + b0 * c02) / det
    return True


def _diverging(err, last, it, bound):
    """A Newton point whose residual is not finite, huge, or no longer halving after two steps."""
    return not math.isfinite(err) or err > bound or (it >= 2 and err > 0.5 * last)


def normal_gaps(problem, pinion_blank, gear_blank, pair_of_point, coords, start, phi1, origin, axes, rotation,
                errors, tol, max_iter, out_lu, out_gear, out_rates, out_margin, out_ok, out_p1, out_p2):
    """The unloaded gap of loaded-TCA cells (beveloid/ltca.py), one point per cell.

    Point m belongs to pair q = pair_of_point[m]; start[q] holds unknowns (UNKNOWNS order).  The
    pinion flank point whose offset from origin[q] (S_1) has the components coords[m] on the
    two rows of axes[q] (2x2 Newton on the pinion surface jet, from start[q]'s pinion l, u), then
    the gear point on the pinion's normal line R_f2(l2, u2) = R_f1 + s n_f1 (3x3 Newton on
    Eq 38's position rows, from start[q]'s gear l, u, at the pinion angle phi1[q] and start[q]'s
    gear angle; rotation[q] is the pinion's L_f1).  Outputs per point: out_lu (l1, u1); out_gear
    (l2, u2, s); out_rates (ds/dphi'_2 by the implicit function theorem, the moment arm
    n_f1 . dR_f1/dphi'_1);
    out_margin the smallest margin of both points to their blanks; out_ok 1 when both Newtons
    converged; out_p1, out_p2 the points in S_1 and S_2.
    """
    pinion_model, gear_model, flank, pinion_params, gear_params, pair = problem
    M = coords.shape[0]
    # serial: a parallel loop measured 3x slower here (small work per point, one thread)
    s = scratch()
    ws, F, J, Je, Jp, dx, e = s.ws, s.F, s.J, s.Je, s.Jp, s.dx, s.e
    for i in range(N_ERRORS):
        e[i] = errors[i]
    pt = np.empty(3)
    nm = np.empty(3)
    dp = np.empty((3, 2))
    dn = np.empty((3, 2))
    nf = np.empty(3)
    x = np.empty(N_UNKNOWNS)
    warm = False
    for m in range(M):
        # continuation: the previous point of the same pair, when it converged, is the start
        warm = warm and m > 0 and pair_of_point[m - 1] == pair_of_point[m]
        warm = _normal_gap_point(problem, pinion_blank, gear_blank, pair_of_point[m], coords, m, start, phi1,
                                 origin, axes, rotation, tol, max_iter, out_lu, out_gear, out_rates, out_margin,
                                 out_ok, out_p1, out_p2, ws, F, J, Je, Jp, dx, e, pt, nm, dp, dn, nf, x, warm)


def _normal_gap_point(problem, pinion_blank, gear_blank, q, coords, m, start, phi1, origin, axes, rotation, tol,
                      max_iter, out_lu, out_gear, out_rates, out_margin, out_ok, out_p1, out_p2, ws, F, J, Je, Jp,
                      dx, e, pt, nm, dp, dn, nf, x, warm):
    """Point m of :func:`normal_gaps` with the caller's scratch arrays; starts from x as it is
    (the previous point's solution) when ``warm``, else from start[q].  True if it converged."""
    pinion_model, gear_model, flank, pinion_params, gear_params, pair = problem
    for i in range(N_UNKNOWNS):
        if not warm or i == GEAR_ANGLE:
            x[i] = start[q, i]
    ok1 = False
    last = 1e300
    for it in range(max_iter + 1):
        surface_jet_point(pinion_model, flank, x[PINION_L], x[PINION_U], pinion_params, pt, nm, dp, dn)
        f0 = -coords[m, 0]
        f1 = -coords[m, 1]
        a00 = 0.0
        a01 = 0.0
        a10 = 0.0
        a11 = 0.0
        for k in range(3):
            f0 += axes[q, 0, k] * (pt[k] - origin[q, k])
            f1 += axes[q, 1, k] * (pt[k] - origin[q, k])
            a00 += axes[q, 0, k] * dp[k, 0]
            a01 += axes[q, 0, k] * dp[k, 1]
            a10 += axes[q, 1, k] * dp[k, 0]
            a11 += axes[q, 1, k] * dp[k, 1]
        err = max(abs(f0), abs(f1))
        if err < tol:
            ok1 = True
            break
        if it == max_iter or _diverging(err, last, it, 1e3):
            break
        last = err
        det = a00 * a11 - a01 * a10
        if det == 0.0:
            break
        x[PINION_L] += (-f0 * a11 + f1 * a01) / det
        x[PINION_U] += (-a00 * f1 + a10 * f0) / det
    out_lu[m, 0] = x[PINION_L]
    out_lu[m, 1] = x[PINION_U]
    for i in range(3):
        nf[i] = rotation[q, i, 0] * nm[0] + rotation[q, i, 1] * nm[1] + rotation[q, i, 2] * nm[2]
    s = 0.0
    ok2 = False
    last = 1e300
    if ok1:
        for it in range(max_iter + 1):
            evaluate(problem, x, phi1[q], e, ws, F, J, Je, Jp)
            g0 = F[0] + s * nf[0]
            g1 = F[1] + s * nf[1]
            g2 = F[2] + s * nf[2]
            err = max(abs(g0), max(abs(g1), abs(g2)))
            if err < tol:
                ok2 = True
                break
            if it == max_iter or _diverging(err, last, it, 1e3):
                break
            last = err
            if not _solve3(J[0, GEAR_L], J[0, GEAR_U], nf[0], J[1, GEAR_L], J[1, GEAR_U], nf[1], J[2, GEAR_L], J[2, GEAR_U], nf[2],
                           -g0, -g1, -g2, dx):
                break
            x[GEAR_L] += dx[0]
            x[GEAR_U] += dx[1]
            s += dx[2]
    out_gear[m, 0] = x[GEAR_L]
    out_gear[m, 1] = x[GEAR_U]
    out_gear[m, 2] = s
    out_ok[m] = 0
    out_margin[m] = -1e300
    out_rates[m, 0] = 0.0
    out_rates[m, 1] = 0.0
    if ok2 and _solve3(J[0, GEAR_L], J[0, GEAR_U], nf[0], J[1, GEAR_L], J[1, GEAR_U], nf[1], J[2, GEAR_L], J[2, GEAR_U], nf[2],
                       -J[0, GEAR_ANGLE], -J[1, GEAR_ANGLE], -J[2, GEAR_ANGLE], dx):
        out_ok[m] = 1
        out_rates[m, 0] = dx[2]
        out_rates[m, 1] = nf[0] * Jp[0] + nf[1] * Jp[1] + nf[2] * Jp[2]
        margin, _ = contact_margin_point(x, pinion_blank, gear_blank, ws)
        out_margin[m] = margin
        p1 = ws.pinion_point
        p2 = ws.gear_point
        for i in range(3):
            out_p1[m, i] = p1[i]
            out_p2[m, i] = p2[i]
        return True
    for i in range(3):
        out_p1[m, i] = math.nan
        out_p2[m, i] = math.nan
    return False

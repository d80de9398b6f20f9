"""Normal gaps of the loaded TCA: from a point on one flank along its normal to the mating flank.

Plain Python in numba's subset: compiled with the rest of the core by
:mod:`beveloid.solver.backends` (see :mod:`beveloid.solver.core`)."""
import math
import typing

import numpy as np

from ..generated.contact_system_scalar import position_residual_point
from ..generated.layouts import AssemblyErrors, MeshState
from ..generated.tca_kernels import UNKNOWNS
from ..generated.tca_kernels_scalar import N_UNKNOWNS, contact_margin_point, surface_jet_point
from .newton import FINAL_STEP_K, FINAL_STEP_RESIDUAL_MM, GEAR_ANGLE, Scratch, scratch

#: where normal_gaps finds each unknown (by the generated names; numba reads them as constants)
PINION_L = UNKNOWNS.index("pinion_l_mm")
PINION_U = UNKNOWNS.index("pinion_u_mm")
GEAR_L = UNKNOWNS.index("gear_l_mm")
GEAR_U = UNKNOWNS.index("gear_u_mm")
#: how _normal_gap_point starts a point: from the pair's start, ahead along the points before it, or along
#: the previous point's tangents (where no line of points leads to it: a turn of the serpentine)
START_COLD, START_AHEAD, START_TANGENT = 0, 1, 2
#: where the mesh state (MeshState: the gear Newton's errors and angles, by name) holds each assembly error
STATE_ERRORS = np.array([MeshState._fields.index(n) for n in AssemblyErrors._fields], dtype=np.int64)
STATE_PINION_ANGLE = MeshState._fields.index("pinion_angle_rad")
STATE_GEAR_ANGLE = MeshState._fields.index("gear_angle_rad")
N_STATE = len(MeshState._fields)
#: each packed trigonometric entry of MeshState (its DERIVED "<sin|cos|tan>_<angle>"): (its slot, the angle's
#: slot, 0 sin / 1 cos / 2 tan)
STATE_TRIG = np.array([(MeshState._fields.index(n), MeshState._fields.index(n.split("_", 1)[1]),
                        ("sin", "cos", "tan").index(n.split("_", 1)[0])) for n in MeshState.DERIVED], dtype=np.int64)


class GapScratch(typing.NamedTuple):
    """Work arrays of normal_gaps (one thread)."""

    s: Scratch  # the Eq 38 evaluation (newton.Scratch); its workspace holds both surface jets
    normal_f: np.ndarray  # (3,) the pinion normal in S_f
    x: np.ndarray  # (N_UNKNOWNS,) the unknowns of the current point
    matrix: np.ndarray  # (3, 3) the gear Newton's system
    rhs: np.ndarray  # (3,)
    state: np.ndarray  # (N_STATE,) the mesh state of pair state_pair[0] (:func:`_mesh_state`)
    state_pair: np.ndarray  # (1,) int64: the pair whose state ``state`` holds (-1: none yet)


def _solve3(A, b, out):
    """out = A^-1 b for a 3x3 system by Cramer's rule; False if A is singular or not finite."""
    a00, a01, a02 = A[0, 0], A[0, 1], A[0, 2]
    a10, a11, a12 = A[1, 0], A[1, 1], A[1, 2]
    a20, a21, a22 = A[2, 0], A[2, 1], A[2, 2]
    b0, b1, b2 = b[0], b[1], b[2]
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


def _final_step(err, size, tol):
    """A Newton step of largest component ``size`` (mm) from a residual ``err`` after which the residual is
    below ``tol`` without evaluating again (the solver core's test: :data:`newton.FINAL_STEP_K`)."""
    return err <= FINAL_STEP_RESIDUAL_MM and FINAL_STEP_K * size * size <= tol


def _gear_system(J, nf, A):
    """The gear Newton's 3x3 matrix: d/d(l2, u2) of Eq 38's position rows and the pinion normal."""
    for r in range(3):
        A[r, 0] = J[r, GEAR_L]
        A[r, 1] = J[r, GEAR_U]
        A[r, 2] = nf[r]


def normal_gaps(problem, request, out):
    """The unloaded gap of loaded-TCA cells (beveloid/ltca), one point per cell: the
    :class:`records.GapRequest` ``request`` into the :class:`records.GapOutput` ``out``.

    Point m belongs to pair q = request.pair_of_point[m]; start[q] holds unknowns (UNKNOWNS
    order).  The
    pinion flank point whose offset from origin[q] (S_1) has the components coords[m] on the
    two rows of axes[q] (2x2 Newton on the pinion surface jet, from start[q]'s pinion l, u), then
    the gear point on the pinion's normal line R_f2(l2, u2) = R_f1 + s n_f1 (3x3 Newton on
    Eq 38's position rows, from start[q]'s gear l, u, at the pinion angle pinion_angle[q] and
    start[q]'s gear angle; rotation[q] is the pinion's L_f1).  Outputs per point: pinion_lu
    (l1, u1); gear_lu_gap (l2, u2, s); rates (ds/dphi'_2 by the implicit function theorem, the
    moment arm n_f1 . dR_f1/dphi'_1); margin the smallest margin of both points to their blanks;
    ok 1 when both Newtons converged; pinion_point, gear_point the points in S_1 and S_2 (nan, and the gap
    nan, where they did not).  A continued point whose gap jumps (:func:`_jumped`) is solved again from
    start[q].
    """
    pair_of_point = request.pair_of_point
    M = request.coords.shape[0]
    # serial: a parallel loop measured 3x slower here (small work per point, one thread)
    w = GapScratch(s=scratch(), normal_f=np.empty(3), x=np.empty(N_UNKNOWNS), matrix=np.empty((3, 3)),
                   rhs=np.empty(3), state=np.empty(N_STATE), state_pair=np.full(1, -1, dtype=np.int64))
    warm = False
    for m in range(M):
        # continuation: the previous point of the same pair, when it converged, is the start; when the
        # point before it converged too and the three lie on a line, the start is extrapolated along it
        # (quadratically from three points at equal steps)
        warm = warm and m > 0 and pair_of_point[m - 1] == pair_of_point[m]
        t = _line_step(request, out, m) if warm else 0.0
        quad = abs(t - 1.0) < 1e-9 and m >= 3 and abs(_line_step(request, out, m - 1) - 1.0) < 1e-9
        # the retries pass a bool computed at run time (always False), not the literal False: numba typed a
        # literal argument as Literal[bool] and compiled _normal_gap_point a second time for it
        linear = m < 0
        # likewise a run-time START_COLD: numba types the module's constant as Literal[int] and compiled
        # _normal_gap_point a second time for it (benchmarks/compile_signatures.py lists such repeats)
        cold = np.int64(START_COLD)
        # how each try starts (START_*); only the first may start from the previous point's derivatives (the
        # scratch then still holds its last evaluation)
        retry = START_AHEAD if warm else cold
        first = (START_TANGENT if t == 0.0 else START_AHEAD) if warm else cold
        ok = _normal_gap_point(problem, request, m, out, w, first, t, quad)
        if not ok and quad:  # an extrapolated start failed: again from fewer points
            ok = _normal_gap_point(problem, request, m, out, w, retry, t, linear)
        if not ok and t != 0.0:
            ok = _normal_gap_point(problem, request, m, out, w, retry, 0.0, linear)
        if ok and warm and _jumped(request, out, m):
            # the continuation reached another intersection of the normal line with the (extended) gear
            # surface, tens of mm away; the points after it would start there: again from the pair's start
            ok = _normal_gap_point(problem, request, m, out, w, cold, 0.0, linear)
        warm = ok


#: a point's gap may change from its neighbour's by at most this much per mm moved (plus GAP_JUMP_MM): the
#: mating flanks' gap rises far slower than the distance along them (its slope is the angle between them);
#: a faster change is another intersection of the normal line with the extended gear surface (a random
#: design, m_n 5, 19/55: 27 um at one probe, 281 mm at the next, 5 mm away)
GAP_SLOPE_LIMIT = 2.0
GAP_JUMP_MM = 0.05


def _jumped(request, out, m):
    """Whether point m's gap departs from point m - 1's (the same pair's, converged) by more than the flanks
    allow over the step between them (:data:`GAP_SLOPE_LIMIT`)."""
    c = request.coords
    step = math.hypot(c[m, 0] - c[m - 1, 0], c[m, 1] - c[m - 1, 1])
    return abs(out.gear_lu_gap[m, 2] - out.gear_lu_gap[m - 1, 2]) > GAP_SLOPE_LIMIT * step + GAP_JUMP_MM


def _line_step(request, out, m):
    """The step from point m - 1 to point m in units of the step from m - 2 to m - 1 when the three
    points of one pair lie on a line (cosine > 0.9) at steps within a factor of two of each other, both
    earlier points converged; else 0 (no extrapolation)."""
    if m < 2 or request.pair_of_point[m - 2] != request.pair_of_point[m] or out.ok[m - 2] != 1:
        return 0.0
    c = request.coords
    a0 = c[m - 1, 0] - c[m - 2, 0]
    a1 = c[m - 1, 1] - c[m - 2, 1]
    b0 = c[m, 0] - c[m - 1, 0]
    b1 = c[m, 1] - c[m - 1, 1]
    aa = a0 * a0 + a1 * a1
    bb = b0 * b0 + b1 * b1
    ab = a0 * b0 + a1 * b1
    if not (aa > 0.0 and bb > 0.0 and ab > 0.9 * math.sqrt(aa * bb)):
        return 0.0
    t = ab / aa
    return t if 0.5 <= t <= 2.0 else 0.0


def _ahead(a, m, c, t, quad):
    """Column c of the rows before row m of ``a`` carried on to row m: row m - 1 (t = 0), extrapolated
    by t times its step from row m - 2, or (``quad``) the parabola through rows m - 3 .. m - 1 at equal
    steps."""
    v = a[m - 1, c]
    if t == 0.0:  # (rows before m - 1 are only read when used: they may not exist)
        return v
    if quad:
        return 3.0 * (v - a[m - 2, c]) + a[m - 3, c]
    return v + t * (v - a[m - 2, c])


def _pinion_tangent(request, m, q, dp, x):
    """x's pinion l, u (the previous point's) moved by the pinion Newton's step to point m's coordinates
    with the previous point's derivatives dp (its residual taken as zero)."""
    axes, c = request.axes, request.coords
    a00 = a01 = a10 = a11 = 0.0
    for k in range(3):
        a00 += axes[q, 0, k] * dp[k, 0]
        a01 += axes[q, 0, k] * dp[k, 1]
        a10 += axes[q, 1, k] * dp[k, 0]
        a11 += axes[q, 1, k] * dp[k, 1]
    det = a00 * a11 - a01 * a10
    if det == 0.0 or not math.isfinite(det):
        return
    f0 = c[m, 0] - c[m - 1, 0]
    f1 = c[m, 1] - c[m - 1, 1]
    x[PINION_L] += (f0 * a11 - f1 * a01) / det
    x[PINION_U] += (a00 * f1 - a10 * f0) / det


def _gear_tangent(out, m, x, gap, J, A, dn, dx):
    """The gear Newton's start (x's gear l, u and the returned gap) for point m: the previous point's
    moved by the step that cancels, to first order, the change of its residual with the pinion point
    (J's pinion columns: the previous point's last Eq 38 Jacobian) and the pinion normal (``dn``, the
    change of n_f1); A: the previous point's gear matrix."""
    d0 = x[PINION_L] - out.pinion_lu[m - 1, 0]
    d1 = x[PINION_U] - out.pinion_lu[m - 1, 1]
    for r in range(3):
        dn[r] = -(J[r, PINION_L] * d0 + J[r, PINION_U] * d1 + gap * dn[r])
    if _solve3(A, dn, dx):
        x[GEAR_L] += dx[0]
        x[GEAR_U] += dx[1]
        gap += dx[2]
    return gap


def _mesh_state(request, q, x, w):
    """w.state: the mesh state of pair q (its errors, pinion angle and x's gear angle, with their sines,
    cosines and tangents), computed when w holds another pair's: the gear Newton of every point of a pair
    runs at that pair's angles."""
    if w.state_pair[0] == q:
        return
    st = w.state
    for i in range(STATE_ERRORS.size):
        st[STATE_ERRORS[i]] = request.errors[i]
    st[STATE_PINION_ANGLE] = request.pinion_angle[q]
    st[STATE_GEAR_ANGLE] = x[GEAR_ANGLE]
    for i in range(STATE_TRIG.shape[0]):
        a = st[STATE_TRIG[i, 1]]
        kind = STATE_TRIG[i, 2]
        st[STATE_TRIG[i, 0]] = math.sin(a) if kind == 0 else (math.cos(a) if kind == 1 else math.tan(a))
    w.state_pair[0] = q


def _gear_side(problem, x, state, s):
    """Eq 38's position rows and their Jacobians (rows 0-2 of s.system's F, J, Jp) at x in the mesh state
    ``state`` (:func:`_mesh_state`), the pinion's jet already in the workspace (the pinion Newton's last
    evaluation, at x's pinion l, u): only the gear's jet is evaluated (a failure made non-finite, s.F[0] = nan).
    The normal rows and the errors' Jacobian, which the gap Newton does not read, are not computed."""
    ws, sy = s.system.ws, s.system
    try:
        surface_jet_point(problem.gear_model, problem.flank, x[GEAR_L], x[GEAR_U], problem.gear_params, ws.gear_point,
                          ws.gear_normal, ws.gear_point_D_lu, ws.gear_normal_D_lu)
        position_residual_point(ws.pinion_point, ws.pinion_point_D_lu, ws.gear_point, ws.gear_point_D_lu, state,
                                problem.pair, sy.F, sy.J, sy.Jp)
    except Exception:  # a math domain error or overflow of a runaway iterate (numba gives nan): not finite
        sy.F[0] = math.nan


def _normal_gap_point(problem, request, m, out, w, how, t, quad):
    """Point m of :func:`normal_gaps` with the caller's :class:`GapScratch` w; starts (``how``) from start[q]
    (:data:`START_COLD`), from the previous point's solution extrapolated along the line of the points before
    it (:data:`START_AHEAD`: :func:`_ahead` with t from :func:`_line_step`), or from the previous point's
    solution moved by the steps its derivatives give (:data:`START_TANGENT`: :func:`_pinion_tangent`,
    :func:`_gear_tangent`; w still holds its last evaluation).  True if it converged."""
    q = request.pair_of_point[m]
    coords, start, origin, axes = request.coords, request.start, request.origin, request.axes
    rotation, tol, max_iter = request.rotation, request.tol_mm, request.max_iter
    s, x = w.s, w.x
    ws = s.system.ws
    warm = how != START_COLD
    tangent = how == START_TANGENT
    pt, nm, dp, dn = ws.pinion_point, ws.pinion_normal, ws.pinion_point_D_lu, ws.pinion_normal_D_lu
    nf, A, g = w.normal_f, w.matrix, w.rhs
    F, J, Jp, dx = s.system.F, s.system.J, s.system.Jp, s.dx
    gap = 0.0
    if warm:
        pl, gl = out.pinion_lu, out.gear_lu_gap
        x[PINION_L], x[PINION_U] = _ahead(pl, m, 0, t, quad), _ahead(pl, m, 1, t, quad)
        x[GEAR_L], x[GEAR_U], gap = _ahead(gl, m, 0, t, quad), _ahead(gl, m, 1, t, quad), _ahead(gl, m, 2, t, quad)
        x[GEAR_ANGLE] = start[q, GEAR_ANGLE]
        if tangent:
            _pinion_tangent(request, m, q, dp, x)
    else:
        for i in range(N_UNKNOWNS):
            x[i] = start[q, i]
    ok1 = False
    last = 1e300
    for it in range(max_iter + 1):
        surface_jet_point(problem.pinion_model, problem.flank, x[PINION_L], x[PINION_U], problem.pinion_params, pt, nm,
                          dp, dn)
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
        d0 = (-f0 * a11 + f1 * a01) / det
        d1 = (-a00 * f1 + a10 * f0) / det
        x[PINION_L] += d0
        x[PINION_U] += d1
        if _final_step(err, max(abs(d0), abs(d1)), tol):
            # no confirming evaluation: the point and normal carried to the new l, u to first order (their
            # error ~|step|^2); the derivatives stay those of the point one step before (the gear Newton
            # reads none of them)
            for k in range(3):
                pt[k] += dp[k, 0] * d0 + dp[k, 1] * d1
                nm[k] += dn[k, 0] * d0 + dn[k, 1] * d1
            ok1 = True
            break
    out.pinion_lu[m, 0] = x[PINION_L]
    out.pinion_lu[m, 1] = x[PINION_U]
    for i in range(3):
        normal = rotation[q, i, 0] * nm[0] + rotation[q, i, 1] * nm[1] + rotation[q, i, 2] * nm[2]
        g[i] = normal - nf[i]  # (the previous point's normal, for the tangent start)
        nf[i] = normal
    if tangent and ok1:
        gap = _gear_tangent(out, m, x, gap, s.system.J, A, g, dx)
    ok2 = False
    last = 1e300
    if ok1:
        _mesh_state(request, q, x, w)
        for it in range(max_iter + 1):
            _gear_side(problem, x, w.state, s)
            for r in range(3):
                g[r] = -(F[r] + gap * nf[r])
            err = max(abs(g[0]), max(abs(g[1]), abs(g[2])))
            if err < tol:
                ok2 = True
                break
            if it == max_iter or _diverging(err, last, it, 1e3):
                break
            last = err
            _gear_system(J, nf, A)
            if not _solve3(A, g, dx):
                break
            x[GEAR_L] += dx[0]
            x[GEAR_U] += dx[1]
            gap += dx[2]
            if _final_step(err, max(abs(dx[0]), max(abs(dx[1]), abs(dx[2]))), tol):
                # no confirming evaluation: the gear point carried to the new l, u to first order; J, Jp (the
                # rates) and the margins are those of the point one such step before (as newton.newton_update)
                gp, gd = ws.gear_point, ws.gear_point_D_lu
                for k in range(3):
                    gp[k] += gd[k, 0] * dx[0] + gd[k, 1] * dx[1]
                ok2 = True
                break
    out.gear_lu_gap[m, 0] = x[GEAR_L]
    out.gear_lu_gap[m, 1] = x[GEAR_U]
    out.gear_lu_gap[m, 2] = gap
    out.ok[m] = 0
    out.margin[m] = -1e300
    out.rates[m, 0] = 0.0
    out.rates[m, 1] = 0.0
    if ok2:
        _gear_system(J, nf, A)
        for r in range(3):
            g[r] = -J[r, GEAR_ANGLE]
    if ok2 and _solve3(A, g, dx):
        out.ok[m] = 1
        out.rates[m, 0] = dx[2]
        out.rates[m, 1] = nf[0] * Jp[0] + nf[1] * Jp[1] + nf[2] * Jp[2]
        margin, _ = contact_margin_point(x, problem.pinion_blank, problem.gear_blank, s.system.ws)
        out.margin[m] = margin
        p1 = s.system.ws.pinion_point
        p2 = s.system.ws.gear_point
        for i in range(3):
            out.pinion_point[m, i] = p1[i]
            out.gear_point[m, i] = p2[i]
        return True
    for i in range(3):
        out.pinion_point[m, i] = math.nan
        out.gear_point[m, i] = math.nan
    out.gear_lu_gap[m, 2] = math.nan  # no gap (the last iterate's would be read as one: column_shifts fits through it)
    return False

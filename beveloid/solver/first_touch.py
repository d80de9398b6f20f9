"""First touch of the bounded flank patches: the active-set search for edge and corner contact,
the candidate enumeration, and the edge followed along a path (see core.py).

Plain Python in numba's subset: compiled with the rest of the core by
:mod:`beveloid.solver.backends` (see :mod:`beveloid.solver.core`)."""
import math
import typing

import numpy as np

from ..generated.tca_kernels_scalar import (
    N_BOUNDARIES, N_ERRORS, N_MARGINS, N_UNKNOWNS, OPPOSITE_BOUNDARY, EdgeWorkspace, Workspace,
    candidate_system_point, edge_workspace, workspace,
)
from .linalg import copy_into, residual_norm, solve_linear
from .newton import GEAR_ANGLE, SAME_ANGLE_RAD, newton_update, on_patch

#: Active-set rounds of first_touch before it falls back to solving every candidate.
#: "no boundary" in an active set, typed int64: a literal -1 there makes numba compile a second
#: specialization of the function it is passed to and of everything that calls on (~5 s of a fresh
#: install's compile)
NO_BOUNDARY = np.int64(-1)
MAX_ROUNDS = 8
#: the edge path's memory (follow_edge): tangents at the last two points before the previous one,
#: the two steps between them, and how many of the tangents are valid
TRACK_T1, TRACK_T2 = 0, N_UNKNOWNS
TRACK_H1, TRACK_H2, TRACK_VALID = 2 * N_UNKNOWNS, 2 * N_UNKNOWNS + 1, 2 * N_UNKNOWNS + 2
TRACK_SIZE = 2 * N_UNKNOWNS + 3


class CandidateSystem(typing.NamedTuple):
    """One evaluation of a candidate system: what :func:`evaluate_candidate` writes (only these
    are passed per evaluation, as newton.System)."""

    ws: Workspace  # the candidates' surface jets (the tangency's stay in newton.Scratch)
    ews: EdgeWorkspace  # the candidate systems' jets (generated tca_kernels_scalar.EdgeWorkspace)
    margins: np.ndarray  # (N_MARGINS,) both points' flank margins
    F: np.ndarray  # (N_UNKNOWNS,) the candidate system's residual
    J: np.ndarray  # (N_UNKNOWNS, N_UNKNOWNS)
    Je: np.ndarray  # (N_UNKNOWNS, N_ERRORS)
    Jp: np.ndarray  # (N_UNKNOWNS,)


class EdgeScratch(typing.NamedTuple):
    """Work arrays of the first-touch search and of the edge followed along a path (one thread)."""

    system: CandidateSystem  # the last candidate evaluation
    step: np.ndarray  # (N_UNKNOWNS,)
    y: np.ndarray  # (N_UNKNOWNS,) the multipliers' solve
    rhs: np.ndarray  # (N_UNKNOWNS,)
    JT: np.ndarray  # (N_UNKNOWNS, N_UNKNOWNS) J transposed
    x: np.ndarray  # (N_UNKNOWNS,) the first touch found (and followed: follow_edge)
    x_prev: np.ndarray  # (N_UNKNOWNS,) the edge contact before it (follow_edge)
    trial: np.ndarray  # (N_UNKNOWNS,) a candidate's solution (enumerate_candidates)
    tangent: np.ndarray  # (N_UNKNOWNS,) the edge path's tangent (follow_edge)
    track: np.ndarray  # (TRACK_SIZE,) the edge path's last tangents, steps and validity (follow_edge)


def edge_scratch():
    """An :class:`EdgeScratch` (allocate once per thread)."""
    system = CandidateSystem(ws=workspace(), ews=edge_workspace(), margins=np.zeros(N_MARGINS),
                             F=np.empty(N_UNKNOWNS), J=np.empty((N_UNKNOWNS, N_UNKNOWNS)),
                             Je=np.empty((N_UNKNOWNS, N_ERRORS)), Jp=np.empty(N_UNKNOWNS))
    return EdgeScratch(system=system, step=np.empty(N_UNKNOWNS), y=np.empty(N_UNKNOWNS),
                       rhs=np.empty(N_UNKNOWNS), JT=np.empty((N_UNKNOWNS, N_UNKNOWNS)), x=np.empty(N_UNKNOWNS),
                       x_prev=np.empty(N_UNKNOWNS), trial=np.empty(N_UNKNOWNS), tangent=np.empty(N_UNKNOWNS),
                       track=np.zeros(TRACK_SIZE))


def evaluate_candidate(problem, first, second, x, phi1, e, es):
    """The candidate system of the active boundaries (first, second) at x (tca_kernels_scalar)
    into the :class:`CandidateSystem` es.  May raise, as evaluate_unchecked: newton_candidate catches
    it around its loop."""
    candidate_system_point(problem.pinion_model, problem.gear_model, problem.flank, first, second, x, phi1, e,
                           problem.pinion_params, problem.gear_params, problem.pair, problem.pinion_blank,
                           problem.gear_blank, es.ws, es.ews, es.F, es.J, es.Je, es.Jp, es.margins)


def newton_candidate(problem, first, second, x, phi1, e, settings, es):
    """Newton in place on x for one candidate system; (converged, iterations).  es.F, J, Je, Jp
    and margins (es.system) hold the last evaluation (as in :func:`newton`)."""
    scale = settings.scale_mm
    tol = settings.tol_mm
    max_iter = settings.max_iter
    n_mm = 3 + (1 if first >= 0 else 0) + (1 if second >= 0 else 0)
    system = es.system
    done = 0
    try:
        for it in range(max_iter + 1):
            done = it
            evaluate_candidate(problem, first, second, x, phi1, e, system)
            s = newton_update(system.F, system.J, x, es.step, residual_norm(system.F, scale, n_mm), tol, it == max_iter,
                              scale)
            if s == 2:
                return True, it + 1
            if s != 0:
                return s > 0, it
    except Exception:  # as in newton: the same verdict on both backends
        system.F[0] = math.nan
        return False, done
    return False, max_iter


def conflicting(a, b):
    """True if boundaries a and b (indices into CONTACT_BOUNDARIES) cannot be active together:
    the same boundary, or opposite sides of one member's patch."""
    if a < 0 or b < 0:
        return False
    if a == b:
        return True
    if (a < N_BOUNDARIES) != (b < N_BOUNDARIES):
        return False
    return OPPOSITE_BOUNDARY[a % N_BOUNDARIES] == b % N_BOUNDARIES


def multipliers(J, sign, y, rhs, JT):
    """Multipliers of the active boundaries (rows 3 and 4) at a solution whose Jacobian is J:
    J^T y = -sign e_phi'2 (the KKT condition of max sign * phi'_2).  (lambda_3, lambda_4); nan if
    J is singular."""
    for i in range(N_UNKNOWNS):
        for k in range(N_UNKNOWNS):
            JT[i, k] = J[k, i]
        rhs[i] = 0.0
    rhs[N_UNKNOWNS - 1] = -sign
    if not solve_linear(JT, rhs, y):
        return math.nan, math.nan
    return y[3], y[4]


def worst_inactive(margins, first, second, patch_tol):
    """The most violated boundary not in the active set (-1 if all >= -patch_tol)."""
    worst = -1
    wv = -patch_tol
    for i in range(N_MARGINS):
        if i != first and i != second and not on_patch(margins[i], patch_tol) and margins[i] < wv:
            wv = margins[i]
            worst = i
    return worst


def first_touch(problem, x, first, second, phi1, e, settings, es):
    """Active-set search for the first touch from x with the active set (first, second).  In
    place on x; returns (found, first, second, Newton iterations).  J, Jp of ``es.system`` hold the final
    system."""
    sign = settings.first_touch_sign
    patch_tol = settings.patch_tol_mm
    margins, J, y, rhs, JT = es.system.margins, es.system.J, es.y, es.rhs, es.JT
    a = first
    b = second
    its = 0
    for _ in range(MAX_ROUNDS):
        conv, it = newton_candidate(problem, a, b, x, phi1, e, settings, es)
        its += it
        if not conv:
            return False, a, b, its
        worst = worst_inactive(margins, a, b, patch_tol)
        if worst >= 0:
            if a < 0:
                a = worst
            elif b < 0:
                if conflicting(a, worst):
                    a = worst
                else:
                    b = worst
            elif conflicting(a, worst):
                a = worst
            elif conflicting(b, worst):
                b = worst
            else:
                la, lb = multipliers(J, sign, y, rhs, JT)
                if la < lb:
                    a = worst
                else:
                    b = worst
            if b >= 0 and b < a:
                a, b = b, a
            continue
        if a < 0:
            return True, a, b, its
        la, lb = multipliers(J, sign, y, rhs, JT)
        if not math.isfinite(la):
            return False, a, b, its
        if b < 0:
            if la < 0.0:
                return False, a, b, its  # not binding: let the enumeration decide
            return True, a, b, its
        if la < 0.0 or lb < 0.0:
            if la < lb:
                a = b
            b = NO_BOUNDARY
            continue
        return True, a, b, its
    return False, a, b, its


def nearest_turn(x, angle):
    """Turn the gear angle of x by whole turns to within pi of ``angle``: the gear in the same
    place (every system here is 2 pi-periodic in phi'_2), on the branch of the pair's tangency.
    A search that wanders a turn away would otherwise look more extreme than any real contact."""
    turns = math.floor((x[GEAR_ANGLE] - angle) / (2 * math.pi) + 0.5)
    if turns != 0:
        x[GEAR_ANGLE] -= 2 * math.pi * turns


def enumerate_candidates(problem, x_start, x, phi1, e, settings, es):
    """Every edge and corner system solved from x_start; the feasible solution with the largest
    sign * phi'_2 is written to x.  Returns (found, first, second, Newton iterations)."""
    sign = settings.first_touch_sign
    patch_tol = settings.patch_tol_mm
    margins, xt = es.system.margins, es.trial
    best = -math.inf
    ba = NO_BOUNDARY
    bb = NO_BOUNDARY
    its = 0
    for a in range(N_MARGINS):
        for b in range(-1, N_MARGINS):
            if b >= 0 and (b <= a or conflicting(a, b)):
                continue
            copy_into(xt, x_start)
            conv, it = newton_candidate(problem, a, b, xt, phi1, e, settings, es)
            its += it
            nearest_turn(xt, x_start[GEAR_ANGLE])
            if conv and worst_inactive(margins, a, b, patch_tol) < 0 and sign * xt[GEAR_ANGLE] > best:
                best = sign * xt[GEAR_ANGLE]
                ba = a
                bb = b
                copy_into(x, xt)
    if ba < 0:
        return False, -1, -1, its
    # leave the winner's system in es (J, Jp for the next point's predictor)
    conv, it = newton_candidate(problem, ba, bb, x, phi1, e, settings, es)
    return True, ba, bb, its + it


def follow_edge(problem, prev_first, prev_second, phi1, phi_prev, e, settings, es):
    """The first touch at phi1 continued from the previous point's edge or corner contact es.x
    (at phi_prev, active set (prev_first, prev_second); kept in es.x_prev), predicted along its exact tangent, without
    solving the Eq 38 tangency: the active-set search from there settles on a feasible point with
    non-negative multipliers (a Karush-Kuhn-Tucker point of "maximize sign * phi'_2") or fails.  When
    the tangency comes back onto the patches the multiplier of the edge goes through zero
    (the edge solution meets the tangency there), the search gives up and the caller solves the
    tangency.  Result in es.x; returns (found, first, second, Newton iterations); found with
    first < 0 (the search dropped every boundary) is left to the caller's tangency solve too.

    ``es.track`` (TRACK_SIZE) carries the edge path's tangents at the two points before the
    previous one, the steps between them and how many are valid (same active set): with one, the
    prediction adds the second-order term from the change of the tangent (as the surface path
    does); with two, also the third-order term of the tangents' quadratic through the three
    points.  The candidate system then usually converges in one Newton step."""
    xe, x_prev, dx, track, rhs = es.x, es.x_prev, es.tangent, es.track, es.rhs
    n = N_UNKNOWNS
    copy_into(x_prev, xe)
    h = phi1 - phi_prev
    for i in range(n):
        rhs[i] = -es.system.Jp[i]
    if abs(h) <= SAME_ANGLE_RAD:
        pass  # the same angle again: no prediction, the stored tangents and steps stay those of the last real step
    elif solve_linear(es.system.J, rhs, dx):
        valid = track[TRACK_VALID]
        h1 = track[TRACK_H1]
        h2 = track[TRACK_H2]
        for i in range(n):
            # x(phi_prev + h) with the tangent t(tau) = t0 + a tau + b tau^2 through the known tangents
            a = 0.0
            b = 0.0
            if valid >= 1.0 and h1 != 0.0:
                d1 = (dx[i] - track[TRACK_T1 + i]) / h1
                a = d1
                if valid >= 2.0 and h2 != 0.0:
                    b = (d1 - (dx[i] - track[TRACK_T2 + i]) / (h1 + h2)) / h2
                    a = d1 + b * h1
            xe[i] += dx[i] * h + a * h * h / 2.0 + b * h * h * h / 3.0
            track[TRACK_T2 + i] = track[TRACK_T1 + i]
            track[TRACK_T1 + i] = dx[i]
        track[TRACK_H2] = h1
        track[TRACK_H1] = h
        track[TRACK_VALID] = min(valid + 1.0, 2.0)
    else:
        track[TRACK_VALID] = 0.0
    found, a, b, its = first_touch(problem, xe, prev_first, prev_second, phi1, e, settings, es)
    if not found or a < 0:
        track[TRACK_VALID] = 0.0
        return False, a, b, its
    # the gear angle moves little between points (a near-singular tangent can throw the prediction far)
    nearest_turn(xe, x_prev[GEAR_ANGLE])
    if a != prev_first or b != prev_second:
        track[TRACK_VALID] = 0.0  # the stored tangents belong to the previous active set
    return True, a, b, its

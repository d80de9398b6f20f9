"""The contact solver, written once: Newton on Eq 38, error homotopy, path continuation,
classification, and the first touch of the bounded flank patches (edge and corner contact).

Every function here is plain Python over floats and small numpy arrays, in the subset that
numba compiles.  :mod:`beveloid.solver.backends` runs the same functions either as they are
("numpy" backend, the reference) or compiled by numba ("compiled" backend).  They reach the
maths only through the generated glue ``tca_kernels_scalar`` (the Eq 38 system of the two
members' surface models and the flank margins), so a new surface model changes nothing here.

A *problem* is the tuple (pinion_model, gear_model, flank, pinion_params, gear_params, pair)
of model and flank indices and the generated parameter vectors (see beveloid/tca.py).

**First touch.**  A tooth pair's contact is the extreme gear angle (``sign`` * phi'_2 largest,
``sign`` from tca.gap_sign) over the pairs of points of the two bounded patches that coincide.
When the Eq 38 tangency lies on both patches it is that extreme (surface contact, OK).  Otherwise
:func:`first_touch` looks for the Karush-Kuhn-Tucker point of the problem "maximize sign * phi'_2
subject to R_f1 = R_f2 and the eight margins g_i >= 0" by an active-set iteration over the
candidate systems of ``tca_kernels_scalar.candidate_system_point`` (edge: one active boundary;
corner: two): solve the system of the active set by Newton, add the most violated inactive
boundary, drop an active one whose multiplier (from J^T y = -sign e_phi'2, the rows of J being
the gradients of the constraints) has the wrong sign, until the point is feasible with
non-negative multipliers.  Along a path the previous point's active set and solution, predicted
with the exact tangent, start the next point, so a point usually costs one Newton solve; the
Eq 38 tangency is not solved while an edge contact is followed that way (its multiplier turns
negative where the tangency returns onto the patches, and the search then gives up).  If the
iteration does not settle, every candidate system is solved from the tangency and the extreme
feasible solution is kept (:func:`enumerate_candidates`); none feasible means the patches do
not touch (OUTSIDE).  Before the search from the tangency, :func:`patches_apart` tries to prove
that the pinion's patch cannot reach the gear's at any gear angle (out-of-mesh tooth pairs):
then the point is OUTSIDE at once.
"""
import math

import numpy as np

from ..generated.tca_kernels import BOUNDARIES, UNKNOWNS
from ..generated.tca_kernels_scalar import (
    N_BOUNDARIES, N_ERRORS, N_MARGINS, N_UNKNOWNS, OPPOSITE_BOUNDARY, blank_margins_point, candidate_system_point,
    contact_margin_point, contact_system_point, edge_workspace, pinion_in_gear_frame_point, surface_jet_point,
    surface_point, workspace,
)
from .patch_cover import CELL_FIELDS
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
#: Functions that allocate arrays (here and in the generated glue).  The compiled backend keeps
#: numba's reference counting (NRT) for them only: every other function just works on arrays its
#: caller owns, and without the atomic increments and decrements of their references an
#: evaluation of the contact system costs ~28 % less (docs/performance.md).  numba refuses to
#: compile a function outside this list that allocates ("NRT required but not enabled").
ALLOCATING = ("scratch", "edge_scratch", "clearance_scratch", "workspace", "edge_workspace", "solve_paths",
              "solve_point", "normal_gaps", "solve_linear", "contact_points")
#: Active-set rounds of first_touch before it falls back to solving every candidate.
MAX_ROUNDS = 8
#: How often patches_apart may halve a cell of the pinion patch cover (root spheres of a few mm
#: become 1/64 of that) before it gives up the proof.
MAX_SPLITS = 6
#: Newton's residual after a step s is about K |s|^2, K from the system's second derivatives
#: (measured K <= 0.1 /mm on case 1 and its crowned variant: benchmarks/newton_final_step.py).  A
#: step with FINAL_STEP_K |s|^2 <= tol (|s| with the angle times the length scale), taken from a
#: residual of at most FINAL_STEP_RESIDUAL_MM, ends the iteration without evaluating again: a
#: predicted point (the path continuations) then costs one evaluation, not two.  J, Jp and the
#: margins the caller reads are then those of the point one such step (~1e-6 mm) before.
FINAL_STEP_K = 1.0
FINAL_STEP_RESIDUAL_MM = 1e-4
GEAR_ANGLE = UNKNOWNS.index("gear_angle_rad")
#: the form limit is a margin in the rack parameter (l >= 0), not in the point: no sphere test
FORM_LIMIT = BOUNDARIES.index("form limit")
CELL_X, CELL_L, CELL_U = CELL_FIELDS.index("x_mm"), CELL_FIELDS.index("l_mm"), CELL_FIELDS.index("u_mm")
CELL_HALF_L, CELL_HALF_U = CELL_FIELDS.index("half_l_mm"), CELL_FIELDS.index("half_u_mm")
CELL_STRETCH = CELL_FIELDS.index("stretch")
#: the edge path's memory (follow_edge): tangents at the last two points before the previous one,
#: the two steps between them, and how many of the tangents are valid
TRACK_T1, TRACK_T2 = 0, N_UNKNOWNS
TRACK_H1, TRACK_H2, TRACK_VALID = 2 * N_UNKNOWNS, 2 * N_UNKNOWNS + 1, 2 * N_UNKNOWNS + 2
TRACK_SIZE = 2 * N_UNKNOWNS + 3


def scratch():
    """Work arrays of one solver thread: (workspace, F, J, Je, Jp, step, dx, rhs, e)."""
    return (workspace(), np.empty(N_UNKNOWNS), np.empty((N_UNKNOWNS, N_UNKNOWNS)),
            np.empty((N_UNKNOWNS, N_ERRORS)), np.empty(N_UNKNOWNS), np.empty(N_UNKNOWNS), np.empty(N_UNKNOWNS),
            np.empty(N_UNKNOWNS), np.empty(N_ERRORS))


def evaluate_unchecked(problem, x, phi1, e, ws, F, J, Je, Jp):
    """Eq 38 at unknowns x: residual F, d/d unknowns J, d/d errors Je, d/d pinion angle Jp.  May
    raise on a runaway iterate (math domain error, division by zero): callers catch it once
    around their loop (a try per evaluation cost ~15 % of an evaluation, compiled)."""
    pinion_model, gear_model, flank, pinion_params, gear_params, pair = problem
    contact_system_point(pinion_model, gear_model, flank, x, phi1, e, pinion_params, gear_params, pair, ws, F, J, Je,
                         Jp)


def evaluate(problem, x, phi1, e, ws, F, J, Je, Jp):
    """evaluate_unchecked with a failure made non-finite (F[0] = nan) instead of raised."""
    try:
        evaluate_unchecked(problem, x, phi1, e, ws, F, J, Je, Jp)
    except Exception:  # a math domain error or overflow of a runaway iterate (numba gives nan): not finite
        F[0] = math.nan


def copy_into(dst, src):
    """dst[:] = src for vectors, in the subset numba compiles without reference counting."""
    for i in range(src.shape[0]):
        dst[i] = src[i]


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


def newton_update(F, J, x, step, r, tol, last, scale):
    """One Newton decision at residual norm r: 1 converged, -1 failed (not finite, singular, or
    the last iteration), 0 stepped (x += -J^-1 F; F is negated), 2 stepped and converged (a step
    so small that the residual after it is below tol: FINAL_STEP_K)."""
    if not math.isfinite(r):
        return -1
    if r <= tol:
        return 1
    if last:
        return -1
    for i in range(F.shape[0]):
        F[i] = -F[i]
    if not solve_linear(J, F, step):
        return -1
    size = 0.0
    for i in range(x.shape[0]):
        x[i] += step[i]
        size = max(size, abs(step[i]) * (scale if i == GEAR_ANGLE else 1.0))
    if r <= FINAL_STEP_RESIDUAL_MM and FINAL_STEP_K * size * size <= tol:
        return 2
    return 0


def newton(problem, x, phi1, e, scale, tol, max_iter, ws, F, J, Je, Jp, step):
    """Newton in place on x.  Returns (converged, iterations); F, J, Je, Jp and ws hold the
    last evaluation: at the returned x, or one final small step before it (FINAL_STEP_K)."""
    done = 0
    try:
        for it in range(max_iter + 1):
            done = it
            evaluate_unchecked(problem, x, phi1, e, ws, F, J, Je, Jp)
            s = newton_update(F, J, x, step, residual_norm(F, scale), tol, it == max_iter, scale)
            if s == 2:
                return True, it + 1
            if s != 0:
                return s > 0, it
    except Exception:  # an evaluation failed (see evaluate): not converged
        F[0] = math.nan
        return False, done
    return False, max_iter


def on_patch(margin, patch_tol):
    """THE rule of boundary membership, for the TCA's statuses, the edge candidates and the loaded
    TCA's cells: a point lies on its flank patch when its smallest margin (mm) is at least
    -patch_tol.  A point that lies on a boundary within round-off (|margin| ~ 1e-14 mm, which two
    backends or two CPUs may round to either side of 0) is on the patch on every machine; only a
    margin within round-off of -patch_tol itself could be decided differently (tests compare away
    from it).  Works on a float and elementwise on arrays."""
    return margin >= -patch_tol


def classify(converged, margin, patch_tol):
    """Status code of an Eq 38 tangency from convergence and its smallest flank margin (mm): OK on
    both patches (:func:`on_patch`), OUTSIDE off a patch (then first_touch decides), FAILED."""
    if not converged or not math.isfinite(margin):
        return FAILED
    if on_patch(margin, patch_tol):
        return OK
    return OUTSIDE


def edge_scratch():
    """Work arrays of the first-touch search: (edge workspace, margins, F, J, Je, Jp, step, y, rhs, JT)."""
    return (edge_workspace(), np.zeros(N_MARGINS), np.empty(N_UNKNOWNS), np.empty((N_UNKNOWNS, N_UNKNOWNS)),
            np.empty((N_UNKNOWNS, N_ERRORS)), np.empty(N_UNKNOWNS), np.empty(N_UNKNOWNS), np.empty(N_UNKNOWNS),
            np.empty(N_UNKNOWNS), np.empty((N_UNKNOWNS, N_UNKNOWNS)))


def evaluate_candidate(problem, blanks, first, second, x, phi1, e, ws, ews, F, J, Je, Jp, margins):
    """The candidate system of the active boundaries (first, second) at x (tca_kernels_scalar).
    May raise, as evaluate_unchecked: newton_candidate catches it around its loop."""
    pinion_model, gear_model, flank, pinion_params, gear_params, pair = problem
    pinion_blank, gear_blank = blanks
    candidate_system_point(pinion_model, gear_model, flank, first, second, x, phi1, e, pinion_params, gear_params,
                           pair, pinion_blank, gear_blank, ws, ews, F, J, Je, Jp, margins)


def newton_candidate(problem, blanks, first, second, x, phi1, e, scale, tol, max_iter, ws, ews, F, J, Je, Jp, step,
                     margins):
    """Newton in place on x for one candidate system; (converged, iterations).  F, J, Je, Jp and
    margins hold the last evaluation (as in :func:`newton`)."""
    n_mm = 3 + (1 if first >= 0 else 0) + (1 if second >= 0 else 0)
    done = 0
    try:
        for it in range(max_iter + 1):
            done = it
            evaluate_candidate(problem, blanks, first, second, x, phi1, e, ws, ews, F, J, Je, Jp, margins)
            s = newton_update(F, J, x, step, residual_norm(F, scale, n_mm), tol, it == max_iter, scale)
            if s == 2:
                return True, it + 1
            if s != 0:
                return s > 0, it
    except Exception:  # as in newton: the same verdict on both backends
        F[0] = math.nan
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


def first_touch(problem, blanks, sign, x, first, second, phi1, e, scale, tol, max_iter, patch_tol, ws, es):
    """Active-set search for the first touch from x with the active set (first, second).  In
    place on x; returns (found, first, second, Newton iterations).  J, Jp of ``es`` hold the final
    system."""
    ews, margins, F, J, Je, Jp, step, y, rhs, JT = es
    a = first
    b = second
    its = 0
    for _ in range(MAX_ROUNDS):
        conv, it = newton_candidate(problem, blanks, a, b, x, phi1, e, scale, tol, max_iter, ws, ews, F, J, Je, Jp,
                                    step, margins)
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
            b = -1
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


def enumerate_candidates(problem, blanks, sign, x_start, x, phi1, e, scale, tol, max_iter, patch_tol, ws, es, xt):
    """Every edge and corner system solved from x_start; the feasible solution with the largest
    sign * phi'_2 is written to x.  Returns (found, first, second, Newton iterations)."""
    ews, margins, F, J, Je, Jp, step, y, rhs, JT = es
    best = -math.inf
    ba = -1
    bb = -1
    its = 0
    for a in range(N_MARGINS):
        for b in range(-1, N_MARGINS):
            if b >= 0 and (b <= a or conflicting(a, b)):
                continue
            copy_into(xt, x_start)
            conv, it = newton_candidate(problem, blanks, a, b, xt, phi1, e, scale, tol, max_iter, ws, ews, F, J, Je,
                                        Jp, step, margins)
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
    conv, it = newton_candidate(problem, blanks, ba, bb, x, phi1, e, scale, tol, max_iter, ws, ews, F, J, Je, Jp, step,
                                margins)
    return True, ba, bb, its + it


def clearance_scratch():
    """Work arrays of patches_apart: (rotation, translation, margins, margins_D_point, margins_D_l,
    point in S_2, pinion point, normal, point_D_lu, normal_D_lu, stack of cells (l, u, half_l,
    half_u, depth))."""
    return (np.empty((3, 3)), np.empty(3), np.empty(N_BOUNDARIES), np.empty((N_BOUNDARIES, 3)),
            np.empty(N_BOUNDARIES), np.empty(3), np.empty(3), np.empty(3), np.empty((3, 2)), np.empty((3, 2)),
            np.empty((4 * MAX_SPLITS + 4, 5)))


def sphere_outside_blank(p, radius, l, blank, m, mdp, mdl):
    """(the sphere about p lies outside the blank, p itself lies inside it): the sphere is outside
    when some point margin g_i has g_i(p) + radius |grad g_i| < 0 (derivations/patch_clearance.py);
    the form limit (l >= 0) is checked at p only."""
    blank_margins_point(p, l, blank, m, mdp, mdl)
    inside = True
    for b in range(N_BOUNDARIES):
        if m[b] < 0.0:
            inside = False
        if b != FORM_LIMIT and m[b] + radius * math.sqrt(mdp[b, 0] ** 2 + mdp[b, 1] ** 2 + mdp[b, 2] ** 2) < 0.0:
            return True, False
    return False, inside


def patches_apart(problem, cells, pinion_blank, gear_blank, phi1, e, patch_tol, cs):
    """True when the pinion's bounded flank cannot meet the gear's at phi1 for any gear angle
    (derivations/patch_clearance.py): every cell of the pinion patch cover (beveloid/solver/patch_cover.py)
    has its sphere outside the pinion blank (no patch point) or, carried into S_2 at phi'_2 = 0,
    outside the gear blank.  A cell that is neither is cut in four, at most MAX_SPLITS times.
    False when that cannot be shown: a cell centre on the patch and inside the gear blank, or a
    cell still undecided after MAX_SPLITS."""
    pinion_model, gear_model, flank, pinion_params, gear_params, pair = problem
    rot, trans, m, mdp, mdl, q, pt, nm, dp, dn, stack = cs
    pinion_in_gear_frame_point(phi1, e, pair, rot, trans)
    for i in range(cells.shape[0]):
        stretch = cells[i, CELL_STRETCH]
        stack[0, 0] = cells[i, CELL_L]
        stack[0, 1] = cells[i, CELL_U]
        stack[0, 2] = cells[i, CELL_HALF_L]
        stack[0, 3] = cells[i, CELL_HALF_U]
        stack[0, 4] = 0.0
        top = 1
        while top > 0:
            top -= 1
            l, u, hl, hu, depth = stack[top, 0], stack[top, 1], stack[top, 2], stack[top, 3], stack[top, 4]
            if depth == 0.0:
                for a in range(3):
                    pt[a] = cells[i, CELL_X + a]
            else:
                surface_jet_point(pinion_model, flank, l, u, pinion_params, pt, nm, dp, dn)
            radius = math.sqrt(hl * hl + hu * hu) * stretch + patch_tol
            out, on_patch = sphere_outside_blank(pt, radius, l, pinion_blank, m, mdp, mdl)
            if out:
                continue
            for a in range(3):
                q[a] = trans[a] + rot[a, 0] * pt[0] + rot[a, 1] * pt[1] + rot[a, 2] * pt[2]
            out, in_gear = sphere_outside_blank(q, radius, 0.0, gear_blank, m, mdp, mdl)
            if out:
                continue
            if (on_patch and in_gear) or depth >= MAX_SPLITS:
                return False
            for a in range(2):
                for b in range(2):
                    stack[top, 0] = l + (a - 0.5) * hl
                    stack[top, 1] = u + (b - 0.5) * hu
                    stack[top, 2] = 0.5 * hl
                    stack[top, 3] = 0.5 * hu
                    stack[top, 4] = depth + 1.0
                    top += 1
    return True


def follow_edge(problem, blanks, sign, x_prev, prev_first, prev_second, phi1, phi_prev, e, scale, tol, max_iter,
                patch_tol, ws, es, xe, dx, track):
    """The first touch at phi1 continued from the previous point's edge or corner contact x_prev
    (at phi_prev, active set (prev_first, prev_second)), predicted along its exact tangent, without
    solving the Eq 38 tangency: the active-set search from there settles on a feasible point with
    non-negative multipliers (a Karush-Kuhn-Tucker point of "maximize sign * phi'_2") or fails.  When
    the tangency comes back onto the patches the multiplier of the edge goes through zero
    (the edge solution meets the tangency there), the search gives up and the caller solves the
    tangency.  Result in xe; returns (found, first, second, Newton iterations); found with
    first < 0 (the search dropped every boundary) is left to the caller's tangency solve too.

    ``track`` (TRACK_SIZE) carries the edge path's tangents at the two points before the
    previous one, the steps between them and how many are valid (same active set): with one, the
    prediction adds the second-order term from the change of the tangent (as the surface path
    does); with two, also the third-order term of the tangents' quadratic through the three
    points.  The candidate system then usually converges in one Newton step."""
    ews, margins, F, J, Je, Jp, step, y, rhs, JT = es
    n = N_UNKNOWNS
    copy_into(xe, x_prev)
    h = phi1 - phi_prev
    for i in range(n):
        rhs[i] = -Jp[i]
    if solve_linear(J, rhs, dx):
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
    found, a, b, its = first_touch(problem, blanks, sign, xe, prev_first, prev_second, phi1, e, scale, tol, max_iter,
                                   patch_tol, ws, es)
    if not found or a < 0:
        track[TRACK_VALID] = 0.0
        return False, a, b, its
    # the gear angle moves little between points (a near-singular tangent can throw the prediction far)
    nearest_turn(xe, x_prev[GEAR_ANGLE])
    if a != prev_first or b != prev_second:
        track[TRACK_VALID] = 0.0  # the stored tangents belong to the previous active set
    return True, a, b, its


def solve_off_patch(problem, blanks, cells, sign, x_tangency, phi1, e, scale, tol, max_iter, patch_tol, ws, es, cs,
                    xe, xt, track):
    """The first touch at phi1 when the tangency x_tangency is off a patch and no edge contact is
    being followed (:func:`follow_edge`): unless patches_apart proves the patches cannot touch,
    the active-set search from the tangency and, when it does not settle, the enumeration.  Result
    in xe; returns (found, first, second, Newton iterations)."""
    track[TRACK_VALID] = 0.0
    if patches_apart(problem, cells, blanks[0], blanks[1], phi1, e, patch_tol, cs):
        return False, -1, -1, 0
    copy_into(xe, x_tangency)
    found, a, b, its = first_touch(problem, blanks, sign, xe, -1, -1, phi1, e, scale, tol, max_iter, patch_tol, ws,
                                   es)
    if found and a >= 0:
        nearest_turn(xe, x_tangency[GEAR_ANGLE])
        return True, a, b, its
    found, a, b, more = enumerate_candidates(problem, blanks, sign, x_tangency, xe, phi1, e, scale, tol, max_iter,
                                             patch_tol, ws, es, xt)
    return found, a, b, its + more


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


def solve_paths(problem, pinion_blank, gear_blank, pinion_cover, x_ref, phi_ref, errors, phi_grid, scale, tol, max_iter,
                homotopy_steps, patch_tol, sign, x_out, code_out, iters_out, boundary_out, active_out):
    """Error sets (K, N_ERRORS) x pinion angles (N,) sorted ascending: the contact unknowns, status
    codes, Newton iterations (of the Eq 38 tangency and of the first-touch search, when there is
    one), the flank boundary nearest the tangency or, at an edge or corner contact, the (first)
    boundary that carries it (-1 if failed), and the active boundaries (K, N, 2) of an edge or
    corner contact (-1: none).

    x_ref is the aligned contact at phi_ref; pinion_cover the cells of the pinion's flank patch
    (beveloid/solver/patch_cover.py) for the proof that a pair's patches cannot touch.  Per error set: the homotopy in the errors at
    phi_ref, then a march up and a march down the grid with the exact tangent d x / d phi_1 as
    predictor, plus the second-order term from the change of the tangent over the last step once
    two converged points are behind (non-conjugate surfaces, e.g. crowned: one Newton step instead
    of two).  A point that fails restarts the next one from the homotopy's solution.  Where the
    tangency leaves a patch, the first touch (edge or corner contact) is solved and reported;
    ``sign`` (+1 or -1) says which extreme of phi'_2 touches first.  The next points follow that
    edge contact (:func:`follow_edge`) without solving the tangency, until the search from it
    fails (its multiplier changes sign where the tangency comes back onto the patches): then the
    tangency is solved again, from the last edge contact (which meets it there) or, if that does
    not converge, from where the tangency was last solved.
    """
    K = errors.shape[0]
    N = phi_grid.shape[0]
    blanks = (pinion_blank, gear_blank)
    j0 = 0
    while j0 < N and phi_grid[j0] < phi_ref:
        j0 += 1
    for k in prange(K):
        ws, F, J, Je, Jp, step, dx, rhs, e = scratch()
        es = edge_scratch()
        cs = clearance_scratch()
        ews = workspace()  # the candidates' surface jets (ws keeps the tangency's)
        xe = np.empty(N_UNKNOWNS)
        xp = np.empty(N_UNKNOWNS)
        track = np.zeros(TRACK_SIZE)  # the edge path's last tangents, steps and validity (follow_edge)
        xt = np.empty(N_UNKNOWNS)
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
            have_edge = False
            skipped = False  # points followed on an edge since the tangency was last solved
            ea = -1
            eb = -1
            phi_edge = phi_ref
            if direction == 0:
                j, stop, inc = j0, N, 1
            else:
                j, stop, inc = j0 - 1, -1, -1
            while j != stop:
                phi = phi_grid[j]
                if have_edge:
                    # follow the edge contact: the tangency is left unsolved while the edge carries
                    xp[:] = xe
                    found, ea, eb, its = follow_edge(problem, blanks, sign, xp, ea, eb, phi, phi_edge, e, scale, tol,
                                                     max_iter, patch_tol, ews, es, xe, dx, track)
                    if found:
                        phi_edge = phi
                        for i in range(N_UNKNOWNS):
                            x_out[k, j, i] = xe[i]
                        code_out[k, j] = EDGE
                        iters_out[k, j] = its
                        boundary_out[k, j] = ea
                        active_out[k, j, 0] = ea
                        active_out[k, j, 1] = eb
                        skipped = True
                        j += inc
                        continue
                    have_edge = False
                h = phi - prev  # prev: the last tangency solved, perhaps several points back
                predicted = False
                if skipped:
                    # the tangency was left unsolved for a while: start from the last edge contact,
                    # which meets the tangency where the edge stops carrying (a stale prediction
                    # over many steps can make Newton wander, even by whole turns of the gear)
                    xt[:] = x
                    x[:] = xp
                    conv, it = newton(problem, x, phi, e, scale, tol, max_iter, ws, F, J, Je, Jp, step)
                    if not conv:  # then from the tangency where it was last solved
                        x[:] = xt
                        conv, it = newton(problem, x, phi, e, scale, tol, max_iter, ws, F, J, Je, Jp, step)
                    nearest_turn(x, xp[GEAR_ANGLE])
                    skipped = False
                else:
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
                active_out[k, j, 0] = -1
                active_out[k, j, 1] = -1
                if conv and ok_all:
                    margin, which = contact_margin_point(x, pinion_blank, gear_blank, ws)
                    code = classify(True, margin, patch_tol)
                    boundary_out[k, j] = which
                    if code == OUTSIDE:
                        found, ea, eb, its = solve_off_patch(problem, blanks, pinion_cover, sign, x, phi, e, scale, tol,
                                                             max_iter, patch_tol, ews, es, cs, xe, xt, track)
                        have_edge = found
                        if found:
                            code = EDGE
                            phi_edge = phi
                            iters_out[k, j] = it + its
                            boundary_out[k, j] = ea
                            for i in range(N_UNKNOWNS):
                                x_out[k, j, i] = xe[i]
                            active_out[k, j, 0] = ea
                            active_out[k, j, 1] = eb
                    code_out[k, j] = code
                else:
                    code_out[k, j] = FAILED
                    boundary_out[k, j] = -1
                    have_edge = False
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


def contact_points(problem, x, code, p1_out, p2_out):
    """The pinion point in S_1 and the gear point in S_2 (K, N, 3) of the solved contacts x
    (K, N, N_UNKNOWNS) whose status code carries numbers (OK, EDGE); nan elsewhere.  The compiled
    twin of tca.contact_points for a whole sweep (one pass, no temporaries)."""
    pinion_model, gear_model, flank, pinion_params, gear_params, pair = problem
    p = np.empty(3)
    nm = np.empty(3)
    roll = np.empty(1)
    for k in range(x.shape[0]):
        for j in range(x.shape[1]):
            if code[k, j] == OK or code[k, j] == EDGE:
                surface_point(pinion_model, flank, x[k, j, 0], x[k, j, 1], pinion_params, p, nm, roll)
                for i in range(3):
                    p1_out[k, j, i] = p[i]
                surface_point(gear_model, flank, x[k, j, 2], x[k, j, 3], gear_params, p, nm, roll)
                for i in range(3):
                    p2_out[k, j, i] = p[i]
            else:
                for i in range(3):
                    p1_out[k, j, i] = math.nan
                    p2_out[k, j, i] = math.nan


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
    ws, F, J, Je, Jp, step, dx, rhs, e = scratch()
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
        p1 = ws[0]
        p2 = ws[4]
        for i in range(3):
            out_p1[m, i] = p1[i]
            out_p2[m, i] = p2[i]
        return True
    for i in range(3):
        out_p1[m, i] = math.nan
        out_p2[m, i] = math.nan
    return False

"""Pair 0 solved along pinion angles for many error sets (the entry point of tca and sweep), and
the contact points of solved unknowns.

Plain Python in numba's subset: compiled with the rest of the core by
:mod:`beveloid.solver.backends` (see :mod:`beveloid.solver.core`)."""
import math

import numpy as np

from ..generated.tca_kernels_scalar import N_UNKNOWNS, contact_margin_point, surface_point
from .linalg import copy_into, copy_matrix_into, solve_linear
from .newton import EDGE, FAILED, GEAR_ANGLE, OK, OUTSIDE, SAME_ANGLE_RAD, classify, homotopy, newton, scratch
from .first_touch import NO_BOUNDARY, TRACK_VALID, edge_scratch, enumerate_candidates, first_touch, follow_edge, nearest_turn
from .clearance import clearance_scratch, patches_apart


def solve_off_patch(problem, cells, x_tangency, phi1, e, settings, es, cs):
    """The first touch at phi1 when the tangency x_tangency is off a patch and no edge contact is
    being followed (:func:`follow_edge`): unless patches_apart proves the patches cannot touch
    (over the pinion patch cover ``cells``), the active-set search from the tangency and, when it
    does not settle, the enumeration.  Result in es.x; returns (found, first, second, Newton
    iterations)."""
    xe = es.x
    es.track[TRACK_VALID] = 0.0
    if patches_apart(problem, cells, phi1, e, settings.patch_tol_mm, cs):
        return False, -1, -1, 0
    copy_into(xe, x_tangency)
    found, a, b, its = first_touch(problem, xe, NO_BOUNDARY, NO_BOUNDARY, phi1, e, settings, es)
    if found and a >= 0:
        nearest_turn(xe, x_tangency[GEAR_ANGLE])
        return True, a, b, its
    found, a, b, more = enumerate_candidates(problem, x_tangency, xe, phi1, e, settings, es)
    return found, a, b, its + more


def solve_paths(problem, request, settings, out):
    """The :class:`records.PathRequest` ``request``: error sets (K, N_ERRORS) x pinion angles (N,)
    sorted ascending, written to the :class:`records.PathOutput` ``out``: the contact unknowns,
    status codes, Newton iterations (of the Eq 38 tangency and of the first-touch search, when
    there is one), the flank boundary nearest the tangency or, at an edge or corner contact, the
    (first) boundary that carries it (-1 if failed), and the active boundaries (K, N, 2) of an
    edge or corner contact (-1: none).

    request.x_ref is the aligned contact at request.phi_ref; request.pinion_cover the cells of the
    pinion's flank patch (beveloid/solver/patch_cover.py) for the proof that a pair's patches
    cannot touch.  Per error set: the homotopy in the errors at
    phi_ref, then a march up and a march down the grid with the exact tangent d x / d phi_1 as
    predictor, plus the second-order term from the change of the tangent over the last step once
    two converged points are behind (non-conjugate surfaces, e.g. crowned: one Newton step instead
    of two).  A point that fails restarts the next one from the homotopy's solution.  Where the
    tangency leaves a patch, the first touch (edge or corner contact) is solved and reported;
    ``settings.first_touch_sign`` (+1 or -1) says which extreme of phi'_2 touches first.  The next points follow that
    edge contact (:func:`follow_edge`) without solving the tangency, until the search from it
    fails (its multiplier changes sign where the tangency comes back onto the patches): then the
    tangency is solved again, from the last edge contact (which meets it there) or, if that does
    not converge, from where the tangency was last solved.
    """
    errors, phi_grid, phi_ref = request.errors, request.phi_grid, request.phi_ref
    x_out, code_out, iters_out, boundary_out, active_out = out.x, out.status, out.iterations, out.boundary, out.active
    K = errors.shape[0]
    N = phi_grid.shape[0]
    j0 = 0
    while j0 < N and phi_grid[j0] < phi_ref:
        j0 += 1
    # the work arrays once per call (per thread), not per error set: ~3 us of allocations a set,
    # ~6 % of its solve; each set starts from request.x_ref and writes every entry it then reads
    s = scratch()
    J, Jp, dx, rhs, e = s.system.J, s.system.Jp, s.dx, s.rhs, s.e
    es = edge_scratch()
    cs = clearance_scratch()
    xe = es.x  # the edge contact found or followed
    xp = es.x_prev  # the one before it
    xt = np.empty(N_UNKNOWNS)
    x = np.empty(N_UNKNOWNS)
    xs = np.empty(N_UNKNOWNS)  # the homotopy's solution at phi_ref
    xl = np.empty(N_UNKNOWNS)  # the last solution of the march (the start of a prediction that failed)
    Jst = np.empty((N_UNKNOWNS, N_UNKNOWNS))
    Jpst = np.empty(N_UNKNOWNS)
    tprev = np.empty(N_UNKNOWNS)  # tangent at the previous converged point
    for k in range(K):  # on threads over slices of the error sets: beveloid.solver.threads
        copy_into(x, request.x_ref)
        ok_all = homotopy(problem, x, phi_ref, errors[k], settings, s)
        copy_into(xs, x)
        copy_matrix_into(Jst, J)
        copy_into(Jpst, Jp)
        for direction in range(2):
            copy_into(x, xs)
            copy_matrix_into(J, Jst)
            copy_into(Jp, Jpst)
            prev = phi_ref
            good = ok_all
            curved = False  # tprev and hprev hold the last step's tangent and length
            hprev = 0.0
            have_edge = False
            skipped = False  # points followed on an edge since the tangency was last solved
            ea = NO_BOUNDARY
            eb = NO_BOUNDARY
            phi_edge = phi_ref
            if direction == 0:
                j, stop, inc = j0, N, 1
            else:
                j, stop, inc = j0 - 1, -1, -1
            while j != stop:
                phi = phi_grid[j]
                if have_edge:
                    # follow the edge contact: the tangency is left unsolved while the edge carries
                    found, ea, eb, its = follow_edge(problem, ea, eb, phi, phi_edge, e, settings, es)
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
                    copy_into(xt, x)
                    copy_into(x, xp)
                    conv, it = newton(problem, x, phi, e, settings, s)
                    if not conv:  # then from the tangency where it was last solved
                        copy_into(x, xt)
                        conv, it = newton(problem, x, phi, e, settings, s)
                    nearest_turn(x, xp[GEAR_ANGLE])
                    skipped = False
                else:
                    if good:
                        copy_into(xl, x)  # the last solution, before the prediction moves it
                        for i in range(N_UNKNOWNS):
                            rhs[i] = -Jp[i]
                        if solve_linear(J, rhs, dx):
                            predicted = True
                            for i in range(N_UNKNOWNS):
                                x[i] += dx[i] * h
                                if curved and hprev != 0.0:
                                    x[i] += 0.5 * (dx[i] - tprev[i]) / hprev * h * h
                    conv, it = newton(problem, x, phi, e, settings, s)
                    if predicted and not conv:
                        # the prediction threw Newton off (the tangency turned sharply over the last step: where
                        # a relief begins it stays at the relief's start): again from the last solution itself
                        copy_into(x, xl)
                        conv, more = newton(problem, x, phi, e, settings, s)
                        it += more
                        predicted = False
                if abs(h) > SAME_ANGLE_RAD:
                    curved = conv and predicted
                    if curved:
                        copy_into(tprev, dx)
                        hprev = h
                # else: the same angle again (pair k's first angle is pair k-1's last, equal to round-off):
                # the tangent and step behind stay those of the last real step; a step of ~1e-17 rad would
                # divide the second-order term by it and throw the next prediction off the patches
                for i in range(N_UNKNOWNS):
                    x_out[k, j, i] = x[i]
                iters_out[k, j] = it
                active_out[k, j, 0] = -1
                active_out[k, j, 1] = -1
                if conv and ok_all:
                    margin, which = contact_margin_point(x, problem.pinion_blank, problem.gear_blank, s.system.ws)
                    code = classify(True, margin, settings.patch_tol_mm)
                    boundary_out[k, j] = which
                    if code == OUTSIDE:
                        found, ea, eb, its = solve_off_patch(problem, request.pinion_cover, x, phi, e, settings, es,
                                                             cs)
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
                    copy_into(x, xs)  # restart the next point from the reference
                good = conv
                prev = phi
                j += inc


def contact_points(problem, x, code, p1_out, p2_out):
    """The pinion point in S_1 and the gear point in S_2 (K, N, 3) of the solved contacts x
    (K, N, N_UNKNOWNS) whose status code carries numbers (OK, EDGE); nan elsewhere.  The compiled
    twin of tca.contact_points for a whole sweep (one pass, no temporaries)."""
    pinion_model, gear_model, flank = problem.pinion_model, problem.gear_model, problem.flank
    pinion_params, gear_params = problem.pinion_params, problem.gear_params
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

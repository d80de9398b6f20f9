"""Newton on Eq 38, its classification (the one boundary rule, on_patch), the error homotopy and
one point from a start.

Plain Python in numba's subset: compiled with the rest of the core by
:mod:`beveloid.solver.backends` (see :mod:`beveloid.solver.core`)."""
import math
import typing

import numpy as np

from ..generated.tca_kernels import UNKNOWNS
from ..generated.tca_kernels_scalar import N_ERRORS, N_UNKNOWNS, Workspace, contact_system_point, workspace
from ..status import Status
from .linalg import residual_norm, solve_linear

OK = int(Status.OK)
EDGE = int(Status.EDGE)
OUTSIDE = int(Status.OUTSIDE)
FAILED = int(Status.FAILED)
#: Newton's residual after a step s is about K |s|^2, K from the system's second derivatives
#: (measured K <= 0.1 /mm on case 1 and its crowned variant: benchmarks/newton_final_step.py).  A
#: step with FINAL_STEP_K |s|^2 <= tol (|s| with the angle times the length scale), taken from a
#: residual of at most FINAL_STEP_RESIDUAL_MM, ends the iteration without evaluating again: a
#: predicted point (the path continuations) then costs one evaluation, not two.  J, Jp and the
#: margins the caller reads are then those of the point one such step (~1e-6 mm) before.
FINAL_STEP_K = 1.0
FINAL_STEP_RESIDUAL_MM = 1e-4
GEAR_ANGLE = UNKNOWNS.index("gear_angle_rad")
#: two path angles closer than this (rad) are the same point twice (a step of round-off: the loaded
#: cycle's grid holds pair k's first angle and pair k-1's last); the path predictors keep the tangents
#: and steps of the last real step over it, since a second-order term divided by ~1e-17 rad throws the
#: next prediction far off the patches
SAME_ANGLE_RAD = 1e-12


class System(typing.NamedTuple):
    """One evaluation of Eq 38: what :func:`evaluate` writes (the record passed per evaluation
    holds only these: a bigger record costs its fields' copies on every call, compiled)."""

    ws: Workspace  # the surface jets of the last evaluation (generated tca_kernels_scalar.Workspace)
    F: np.ndarray  # (N_UNKNOWNS,) Eq 38 residual
    J: np.ndarray  # (N_UNKNOWNS, N_UNKNOWNS) d F / d unknowns
    Je: np.ndarray  # (N_UNKNOWNS, N_ERRORS) d F / d errors
    Jp: np.ndarray  # (N_UNKNOWNS,) d F / d pinion angle


class Scratch(typing.NamedTuple):
    """Work arrays of one solver thread."""

    system: System  # the last evaluation
    step: np.ndarray  # (N_UNKNOWNS,) a Newton step
    dx: np.ndarray  # (N_UNKNOWNS,) a predictor
    rhs: np.ndarray  # (N_UNKNOWNS,) a right-hand side
    e: np.ndarray  # (N_ERRORS,) the errors of the current homotopy step


def scratch():
    """A :class:`Scratch` (allocate once per thread)."""
    system = System(ws=workspace(), F=np.empty(N_UNKNOWNS), J=np.empty((N_UNKNOWNS, N_UNKNOWNS)),
                    Je=np.empty((N_UNKNOWNS, N_ERRORS)), Jp=np.empty(N_UNKNOWNS))
    return Scratch(system=system, step=np.empty(N_UNKNOWNS),
                   dx=np.empty(N_UNKNOWNS), rhs=np.empty(N_UNKNOWNS), e=np.empty(N_ERRORS))


def evaluate_unchecked(problem, x, phi1, e, s):
    """Eq 38 at unknowns x, pinion angle phi1 and errors e into the :class:`System` s: residual
    s.F, d/d unknowns s.J, d/d errors s.Je, d/d pinion angle s.Jp, the surface jets s.ws.  May
    raise on a runaway iterate (math domain error, division by zero): callers catch it once
    around their loop (a try per evaluation cost ~15 % of an evaluation, compiled)."""
    contact_system_point(problem.pinion_model, problem.gear_model, problem.flank, x, phi1, e, problem.pinion_params,
                         problem.gear_params, problem.pair, s.ws, s.F, s.J, s.Je, s.Jp)


def evaluate(problem, x, phi1, e, s):
    """evaluate_unchecked with a failure made non-finite (s.F[0] = nan) instead of raised."""
    try:
        evaluate_unchecked(problem, x, phi1, e, s)
    except Exception:  # a math domain error or overflow of a runaway iterate (numba gives nan): not finite
        s.F[0] = math.nan


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


def newton(problem, x, phi1, e, settings, s):
    """Newton in place on x (records.Settings: scale_mm, tol_mm, max_iter).  Returns (converged,
    iterations); the :class:`Scratch` s holds the last evaluation (s.system): at the
    returned x, or one final small step before it (FINAL_STEP_K)."""
    scale = settings.scale_mm
    tol = settings.tol_mm
    max_iter = settings.max_iter
    system = s.system
    done = 0
    try:
        for it in range(max_iter + 1):
            done = it
            evaluate_unchecked(problem, x, phi1, e, system)
            decision = newton_update(system.F, system.J, x, s.step, residual_norm(system.F, scale), tol, it == max_iter,
                                     scale)
            if decision == 2:
                return True, it + 1
            if decision != 0:
                return decision > 0, it
    except Exception:  # an evaluation failed (see evaluate): not converged
        system.F[0] = math.nan
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


def homotopy(problem, x, phi_ref, target, settings, s):
    """Carry the solution x at phi_ref from zero errors to ``target`` in settings.homotopy_steps
    equal steps, each predicted along d x / d errors and corrected by Newton.  In place; True if
    every step converged.  On return s.e == target."""
    steps = settings.homotopy_steps
    Je, dx, e, rhs = s.system.Je, s.dx, s.e, s.rhs
    ok = True
    for i in range(e.shape[0]):
        e[i] = 0.0
    for h in range(1, steps + 1):
        evaluate(problem, x, phi_ref, e, s.system)
        for i in range(rhs.shape[0]):
            r = 0.0
            for c in range(e.shape[0]):
                r -= Je[i, c] * target[c] / steps
            rhs[i] = r
        if solve_linear(s.system.J, rhs, dx):
            for i in range(x.shape[0]):
                x[i] += dx[i]
        for c in range(e.shape[0]):
            e[c] = target[c] if h == steps else target[c] * h / steps
        conv, _ = newton(problem, x, phi_ref, e, settings, s)
        ok = ok and conv
    return ok


def solve_point(problem, x, phi1, errors, settings):
    """One Newton solve from the guess x (copied): (x, converged, iterations, residual_norm_mm)."""
    s = scratch()
    xs = x.copy()
    conv, it = newton(problem, xs, phi1, errors, settings, s)
    return xs, conv, it, residual_norm(s.system.F, settings.scale_mm)

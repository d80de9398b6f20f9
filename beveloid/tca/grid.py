"""Pair 0 solved over error sets x pinion angles: the one call into the solver core's paths."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..generated import tca_kernels
from ..solver import Solver, patch_cover
from ..solver.options import SolverOptions
from ..solver.records import PathOutput, PathRequest, settings
from ..status import Status, carries_numbers
from .contact import contact_points, errors_array, newton_tolerance, unknowns
from .reference import first_touch_sign, reference_contact


@dataclass(frozen=True)
class GridSolution:
    """Pair 0 solved for error sets (K) x pinion angles (N)."""

    x: np.ndarray  # (K, N, 5) tca_kernels.UNKNOWNS
    status: np.ndarray  # (K, N) Status codes
    iterations: np.ndarray  # (K, N) Newton iterations
    #: (K, N) index into tca_kernels.CONTACT_BOUNDARIES: the boundary nearest the tangency or, at an
    #: edge or corner contact, the (first) one that carries it; -1 if failed
    boundary: np.ndarray
    active: np.ndarray  # (K, N, 2) CONTACT_BOUNDARIES indices of an edge / corner contact, -1: none


#: solve_grid runs up to this many error sets in one thread (a mesh study, a backlash: one set)
SERIAL_MAX_SETS = 32
GEAR_ANGLE_INDEX = tca_kernels.UNKNOWNS.index("gear_angle_rad")
_FIELDS = ("x", "status", "iterations", "boundary", "active")


def solve_grid(geom, flank, errors, phi_grid, *, solver: Solver | None = None) -> GridSolution:
    """Pair 0 for error sets (K, 5) x pinion angles (N,), in any order.

    ``solver``: a :class:`beveloid.solver.Solver` (None: the default), its backend and tolerances.
    Both backends run the same solver core.  Error sets whose every point failed (the
    homotopy from the aligned contact lost track) are solved again with 4x, then 16x, as many
    homotopy steps.
    """
    solver = Solver.of(solver)
    opts = solver.options
    errors = np.ascontiguousarray(np.atleast_2d(errors_array(errors)), dtype=float)
    sol = _solve_once(geom, flank, errors, phi_grid, solver, opts.homotopy_steps)
    for factor in (4, 16):
        lost = np.nonzero((sol.status == Status.FAILED).all(axis=1))[0]
        if lost.size == 0:
            break
        again = _solve_once(geom, flank, errors[lost], phi_grid, solver, opts.homotopy_steps * factor)
        for name in _FIELDS:
            getattr(sol, name)[lost] = getattr(again, name)
    return sol


def _solve_once(geom, flank, errors, phi_grid, solver, homotopy_steps):
    options = solver.options
    ref = reference_contact(geom, flank, options)
    phi_grid = np.asarray(phi_grid, dtype=float)
    order = np.argsort(phi_grid, kind="stable")
    grid = np.ascontiguousarray(phi_grid[order])
    K, N = errors.shape[0], grid.shape[0]
    out = PathOutput(x=np.empty((K, N, len(tca_kernels.UNKNOWNS))), status=np.empty((K, N), dtype=np.int64),
                     iterations=np.empty((K, N), dtype=np.int64), boundary=np.empty((K, N), dtype=np.int64),
                     active=np.empty((K, N, 2), dtype=np.int64))
    core = solver.announced_core()
    cover = patch_cover.patch_cover(geom, "pinion", flank, options.patch_tol_mm).cells
    # few error sets (a mesh study, a backlash) on the calling thread; more on threads (solver/threads.py)
    solve_paths = core.solve_paths if K > SERIAL_MAX_SETS else core.solve_paths_serial
    request = PathRequest(pinion_cover=cover, x_ref=np.ascontiguousarray(ref.x), phi_ref=float(ref.pinion_angle),
                          errors=errors, phi_grid=grid)
    solve_paths(geom.problem(flank), request, solver_settings(geom, flank, options, homotopy_steps), out)
    off_branch(geom, ref, grid, out)
    if np.array_equal(order, np.arange(N)):  # an ascending grid (the sweep's): no copies back
        return GridSolution(**out._asdict())
    inv = np.empty_like(order)
    inv[order] = np.arange(N)
    return GridSolution(**{k: v[:, inv] for k, v in out._asdict().items()})


def solver_settings(geom, flank, options: SolverOptions, homotopy_steps=None):
    """The core's records.Settings for a flank of a pair under ``options``."""
    return settings(scale_mm=geom.gear.working_pitch_radius_mm, tol_mm=newton_tolerance(geom, options.tol_mm),
                    max_iter=options.max_iter, patch_tol_mm=options.patch_tol_mm,
                    homotopy_steps=options.homotopy_steps if homotopy_steps is None else homotopy_steps,
                    first_touch_sign=first_touch_sign(geom, flank))


#: a contact of pair 0 is that pair's only while its gear angle lies within this many gear pitches
#: of the kinematic one, phi'_2,ref - (N1/N2)(phi'_1 - phi'_1,ref) (its |TE| below half a pitch)
BRANCH_PITCHES = 0.5


def off_branch(geom, ref, grid, out):
    """Mark FAILED (in place, no numbers) every solved point of ``out`` (records.PathOutput) whose
    gear angle is off pair 0's branch: |TE| >= BRANCH_PITCHES gear pitches is another tooth's
    contact, or a search that wandered (e.g. a diverged edge Newton, whole turns or pitches away),
    never pair 0's."""
    x, code = out.x, out.status
    kinematic = unknowns(ref.x).gear_angle_rad - geom.pinion.teeth / geom.gear.teeth * (grid - ref.pinion_angle)
    with np.errstate(invalid="ignore"):
        far = ~(np.abs(x[..., GEAR_ANGLE_INDEX] - kinematic[None, :]) < BRANCH_PITCHES * geom.pitch_angles[1])
    bad = far & carries_numbers(code)
    code[bad] = Status.FAILED
    out.boundary[bad] = -1
    out.active[bad] = -1


def solved_contact_points(geom, flank, x, status, *, solver: Solver | None = None):
    """contact_points of a solved grid x (K, N, 5) with its status codes (K, N): nan where the
    status carries no numbers.  On the compiled backend one pass of the solver core (a sweep's
    500k points: ~2x faster than the whole-array kernels, docs/performance.md)."""
    x = np.ascontiguousarray(x, dtype=float)
    status = np.asarray(status)
    solver = Solver.of(solver)
    if solver.compiled:
        P1 = np.empty(x.shape[:-1] + (3,))
        P2 = np.empty_like(P1)
        solver.core.contact_points(geom.problem(flank), x, np.ascontiguousarray(status, dtype=np.int64), P1, P2)
        return P1, P2
    P1, P2 = contact_points(geom, flank, x)
    none = ~carries_numbers(status)
    P1[none] = np.nan
    P2[none] = np.nan
    return P1, P2

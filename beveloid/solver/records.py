"""The named records that cross into the solver core: what a call asks (the problem, the request,
the settings) and where it writes (the outputs).

Each is a NamedTuple of arrays and numbers: numba takes one as one argument (it passes the
fields, read by name in the core), and numpy code builds it by keyword.  The core's own work
arrays are records too (newton.Scratch, first_touch.EdgeScratch, clearance.ClearanceScratch, the
generated tca_kernels_scalar.Workspace).
"""
from __future__ import annotations

import typing

import numpy as np


class Problem(typing.NamedTuple):
    """One flank of a pair as the core sees it: each member's surface model and parameter vector
    (generated tca_kernels.SURFACE_LAYOUTS), the placement (layouts.PairPlacement) and each member's
    flank blank (layouts.FlankBlank).  ``PairGeometry.problem(flank)`` builds it."""

    pinion_model: int  # index into tca_kernels.MODELS
    gear_model: int
    flank: int  # index into tca_kernels.FLANKS
    pinion_params: np.ndarray  # (PARAMETER_COUNT,)
    gear_params: np.ndarray
    pair: np.ndarray  # layouts.PairPlacement
    pinion_blank: np.ndarray  # layouts.FlankBlank
    gear_blank: np.ndarray


class Settings(typing.NamedTuple):
    """The numbers that steer one call of the core (from solver.options.SolverOptions and the
    pair): build with :func:`settings`, which fixes their types (one compiled signature)."""

    scale_mm: float  # the length that turns the angle rows into mm (the gear's working pitch radius)
    tol_mm: float  # Newton tolerance on the residual in mm
    max_iter: int  # Newton iterations per point
    patch_tol_mm: float  # the boundary rule's tolerance (newton.on_patch)
    homotopy_steps: int  # equal steps from the aligned contact to the errors
    first_touch_sign: float  # +1 / -1: which extreme of phi'_2 is a tooth pair's first touch


def settings(scale_mm, tol_mm, max_iter, patch_tol_mm=1e-9, homotopy_steps=3, first_touch_sign=1.0) -> Settings:
    """A :class:`Settings` with float and int fields as numba types them."""
    return Settings(scale_mm=float(scale_mm), tol_mm=float(tol_mm), max_iter=int(max_iter),
                    patch_tol_mm=float(patch_tol_mm), homotopy_steps=int(homotopy_steps),
                    first_touch_sign=float(first_touch_sign))


class PathRequest(typing.NamedTuple):
    """What paths.solve_paths solves: error sets x pinion angles from the aligned contact."""

    pinion_cover: np.ndarray  # (cells, patch_cover.CELL_FIELDS): the pinion patch's spheres
    x_ref: np.ndarray  # (N_UNKNOWNS,) the aligned contact at phi_ref
    phi_ref: float  # rad
    errors: np.ndarray  # (K, N_ERRORS)
    phi_grid: np.ndarray  # (N,) pinion angles, ascending


class PathOutput(typing.NamedTuple):
    """Where paths.solve_paths writes (the fields of tca.GridSolution)."""

    x: np.ndarray  # (K, N, N_UNKNOWNS)
    status: np.ndarray  # (K, N) int64 Status codes
    iterations: np.ndarray  # (K, N) int64 Newton iterations
    boundary: np.ndarray  # (K, N) int64 CONTACT_BOUNDARIES index, -1 if failed
    active: np.ndarray  # (K, N, 2) int64 active boundaries of an edge / corner contact, -1: none


class GapRequest(typing.NamedTuple):
    """What gaps.normal_gaps solves: M points of Q tooth pairs (see its docstring)."""

    pair_of_point: np.ndarray  # (M,) int64: the pair q of each point
    coords: np.ndarray  # (M, 2) mm on the pair's axes
    start: np.ndarray  # (Q, N_UNKNOWNS) each pair's tangency
    pinion_angle: np.ndarray  # (Q,) rad
    origin: np.ndarray  # (Q, 3) S_1
    axes: np.ndarray  # (Q, 2, 3)
    rotation: np.ndarray  # (Q, 3, 3) the pinion's L_f1
    errors: np.ndarray  # (N_ERRORS,)
    tol_mm: float
    max_iter: int


class GapOutput(typing.NamedTuple):
    """Where gaps.normal_gaps writes, per point."""

    pinion_lu: np.ndarray  # (M, 2) l1, u1
    gear_lu_gap: np.ndarray  # (M, 3) l2, u2 and the gap s (mm) along the pinion normal
    rates: np.ndarray  # (M, 2) ds/dphi'_2 and the moment arm n_f1 . dR_f1/dphi'_1
    margin: np.ndarray  # (M,) the smaller of both points' smallest margins (mm)
    ok: np.ndarray  # (M,) int64: 1 when both Newtons converged
    pinion_point: np.ndarray  # (M, 3) S_1
    gear_point: np.ndarray  # (M, 3) S_2


class ChordRequest(typing.NamedTuple):
    """What chord.ellipse_chords measures: n contacts, each member m (0 pinion, 1 gear)."""

    rotations: np.ndarray  # (2, n, 3, 3) each member's placement in S_f
    translations: np.ndarray  # (2, n, 3)
    start_lu: np.ndarray  # (2, n, 2) each member's (l, u) at the contact
    points: np.ndarray  # (n, 3) the contact in S_f
    bases: np.ndarray  # (n, 2, 3) the tangent plane's basis
    directions: np.ndarray  # (n, 2) the chord's direction in that basis
    caps: np.ndarray  # (n,) mm, the longest chord
    samples: np.ndarray  # fractions of the cap, ascending
    bisections: int

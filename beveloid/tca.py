"""Tooth contact analysis of crossed beveloid gears under the five assembly errors (Eqs 28-38).

Built on the generated kernels only: each member's tooth-surface model (``surface_<model>``),
the Eq 38 contact system composed from them (``tca_kernels``) and the flank margins.  The
contact solver itself is :mod:`beveloid.solver` (one core, a numpy and a compiled backend).

Conventions (the paper is silent on these; see docs/validation.md):

* Flanks are named after the signs of Eqs 1-3 (upper sign = left).  The left flank of the
  pinion meshes with the left flank of the gear (both are the same flank plane of the common
  rack, Eq 18).
* Normals are outward from each tooth, so the contact condition is n_f1 = -n_f2.
* Each member's frame S_i has its origin on the axis in the reference transverse section
  (where its profile shift equals x_t).  That section lies b_c (``reference_section_offset_mm``)
  below the working pitch circle, which passes through the pitch point P of the pitch-cone
  design; default b_c = 0.  Face widths are centred on the working pitch circle.
* Flank boundaries (derivations/flank_boundaries.py): face width (toe and heel at -+W/2 about
  the working pitch circle), tip cone (tip height ``addendum_coefficient * m_n`` above the rack
  pitch plane, parallel to the root cone), form limit l >= 0 (the start of the rack's straight
  edge; no fillet).
* Pair k (k = ..., -1, 0, 1, ...) is pinion tooth k with gear tooth k.  Because each pair's
  solution is pair 0's solution turned by whole tooth pitches, pair 0 is solved on the
  shifted pinion angles and the points are turned back into place.
* TE = phi'_2 - phi'_2,ref + (N1/N2)(phi'_1 - phi'_1,ref), the reference being the contact
  at the pitch point P of the aligned pair on the same flank.
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field

import numpy as np

from . import assembly_errors, patch_cover
from .generated import layouts, tca_kernels
from .geometry import Member, PairGeometry  # noqa: F401  (re-exported: tca.PairGeometry.from_design)
from .solver import backends
from .solver.options import DEFAULT_OPTIONS, SolverOptions  # noqa: F401  (re-exported: tca.SolverOptions)
from .status import Status, carries_numbers

FLANKS = tca_kernels.FLANKS
#: The five assembly errors, in the order of every (..., 5) error array (generated layout).
ERROR_NAMES = layouts.AssemblyErrors._fields
ERROR_UNITS = layouts.AssemblyErrors.UNITS




def errors_array(errors) -> np.ndarray:
    """AssemblyErrors or (dx_mm, dy_mm, dz_mm, vertical_rad, horizontal_rad) -> array (..., 5)."""
    e = np.asarray(errors, dtype=float)
    if e.shape[-1:] != (len(ERROR_NAMES),):
        raise ValueError(f"errors must have {len(ERROR_NAMES)} components {ERROR_NAMES}, got shape {e.shape}")
    return e


def unknowns(x) -> layouts.ContactUnknowns:
    """Named views of solver unknowns x (..., 5): .pinion_l_mm, ..., .gear_angle_rad."""
    return layouts.ContactUnknowns(*np.moveaxis(np.asarray(x), -1, 0))


def contact_points(geom, flank, x):
    """(pinion point in S_1, gear point in S_2) of contacts x (..., 5)."""
    u = unknowns(x)
    return (surface(geom, "pinion", flank, u.pinion_l_mm, u.pinion_u_mm).point,
            surface(geom, "gear", flank, u.gear_l_mm, u.gear_u_mm).point)


def solved_contact_points(geom, flank, x, status, backend="auto"):
    """contact_points of a solved grid x (K, N, 5) with its status codes (K, N): nan where the
    status carries no numbers.  On the compiled backend one pass of the solver core (a sweep's
    500k points: ~2x faster than the whole-array kernels, docs/performance.md)."""
    x = np.ascontiguousarray(x, dtype=float)
    status = np.asarray(status)
    ns = _core(backend)
    if ns.compiled:
        P1 = np.empty(x.shape[:-1] + (3,))
        P2 = np.empty_like(P1)
        ns.contact_points(geom.problem(flank), x, np.ascontiguousarray(status, dtype=np.int64), P1, P2)
        return P1, P2
    P1, P2 = contact_points(geom, flank, x)
    none = ~carries_numbers(status)
    P1[none] = np.nan
    P2[none] = np.nan
    return P1, P2


def _check_flank(flank):
    if flank not in FLANKS:
        raise ValueError(f"flank = {flank!r}: must be one of {', '.join(FLANKS)}")
    return flank


# --------------------------------------------------------------------------------------------
# kernels (numpy, batched)
# --------------------------------------------------------------------------------------------
def evaluate(geom: PairGeometry, flank, x, phi1, errors) -> tca_kernels.ContactSystem:
    """Eq 38 and its Jacobians at unknowns x (..., 5), pinion angles phi1 (...), errors (..., 5)."""
    _check_flank(flank)
    return tca_kernels.contact_system(geom.pinion.tooth_surface, geom.gear.tooth_surface, flank, x, phi1,
                                      errors_array(errors), geom.surface_params("pinion"),
                                      geom.surface_params("gear"), geom.placement())


def surface(geom: PairGeometry, which, flank, l, u):
    """(point, normal, roll_angle) of a member's flank at (l, u)."""
    return geom.surface(which, _check_flank(flank), l, u)


def surface_jacobian(geom, which, flank, l, u):
    """[dR/dl, dR/du] (..., 3, 2) of a member's flank."""
    return geom.surface_jet(which, _check_flank(flank), l, u).point_D_lu


def contact_margins(geom, flank, x):
    """Margins (..., 8) in mm of contacts x (..., 5) to both blanks (tca_kernels.CONTACT_BOUNDARIES)."""
    x = np.asarray(x, dtype=float)
    p1, p2 = contact_points(geom, flank, x)
    return tca_kernels.contact_margins(x, p1, p2, geom.pinion.blank(), geom.gear.blank())


def boundary_margins(geom, flank, x):
    """(smallest margin in mm, name of that boundary) of contacts x (..., 5); > 0 is inside."""
    M = contact_margins(geom, flank, x)
    k = np.argmin(M, axis=-1)
    return np.take_along_axis(M, k[..., None], -1)[..., 0], np.asarray(tca_kernels.CONTACT_BOUNDARIES)[k]


def newton_tolerance(geom, tol_mm=DEFAULT_OPTIONS.tol_mm):
    """tol_mm, or the round-off floor of the position residual for large coordinates."""
    scale = geom.gear.working_pitch_radius_mm
    return max(tol_mm, 64 * np.finfo(float).eps * (abs(geom.gear.axial_placement_mm) + geom.offset_mm + scale))


def resolve_backend(backend):
    """'auto' -> 'compiled' when numba is installed, else 'numpy'."""
    return backends.resolve(backend)


# --------------------------------------------------------------------------------------------
# reference contact at the pitch point
# --------------------------------------------------------------------------------------------
def _point_at_radius(geom, which, flank, radius, z):
    """(l, u) of the flank point at the given radius in the transverse section z; polar angle."""
    m = geom.member(which)
    l, u = m.cutter_addendum_mm / math.cos(geom.normal_pressure_angle), 0.0
    for _ in range(30):
        jet = geom.surface_jet(which, flank, l, u)
        p, J = jet.point, jet.point_D_lu
        rad = math.hypot(p[0], p[1])
        F = np.array([rad - radius, p[2] - z])
        G = np.array([[(p[0] * J[0, 0] + p[1] * J[1, 0]) / rad, (p[0] * J[0, 1] + p[1] * J[1, 1]) / rad],
                      [J[2, 0], J[2, 1]]])
        d = np.linalg.solve(G, -F)
        l, u = l + d[0], u + d[1]
        if abs(d).max() < 1e-12 * max(1.0, radius):  # quadratic convergence: the last step was round-off
            break
    p = geom.surface(which, flank, l, u).point
    return l, u, math.atan2(p[1], p[0])


@dataclass(frozen=True)
class Reference:
    flank: str
    pinion_angle: float
    x: np.ndarray  # tca_kernels.UNKNOWNS at the pitch point, aligned


def _core(backend="numpy", announce=False):
    ns = backends.namespace(resolve_backend(backend))
    if announce:
        backends.notify_compiling(ns)
    return ns


@functools.lru_cache(maxsize=64)
def reference_contact(geom: PairGeometry, flank: str) -> Reference:
    """Contact of the aligned pair at the pitch point P (the TE reference); cached per geometry."""
    _check_flank(flank)
    p, g = geom.pinion, geom.gear
    l1, u1, psi1 = _point_at_radius(geom, "pinion", flank, p.working_pitch_radius_mm, p.reference_section_offset_mm)
    l2, u2, psi2 = _point_at_radius(geom, "gear", flank, g.working_pitch_radius_mm, g.reference_section_offset_mm)
    phi1 = p.pitch_point_angle - psi1
    phi2 = g.pitch_point_angle - psi2
    x0 = np.asarray(layouts.ContactUnknowns(pinion_l_mm=l1, pinion_u_mm=u1, gear_l_mm=l2, gear_u_mm=u2,
                                            gear_angle_rad=phi2), dtype=float)
    opts = DEFAULT_OPTIONS
    x, conv, _, res = _core().solve_point(geom.problem(flank), x0, phi1, np.zeros(len(ERROR_NAMES)),
                                          geom.gear.working_pitch_radius_mm, newton_tolerance(geom, opts.tol_mm),
                                          opts.max_iter)
    if not conv:
        raise RuntimeError(f"no contact at the pitch point on the {flank} flank (residual {res:.2e} mm)")
    return Reference(flank, phi1, x)


# --------------------------------------------------------------------------------------------
# the solver over error sets x pinion angles
# --------------------------------------------------------------------------------------------
@dataclass
class GridSolution:
    """Pair 0 solved for error sets (K) x pinion angles (N)."""

    x: np.ndarray  # (K, N, 5) tca_kernels.UNKNOWNS
    status: np.ndarray  # (K, N) Status codes
    iterations: np.ndarray  # (K, N) Newton iterations
    #: (K, N) index into tca_kernels.CONTACT_BOUNDARIES: the boundary nearest the tangency or, at an
    #: edge or corner contact, the (first) one that carries it; -1 if failed
    boundary: np.ndarray
    active: np.ndarray = None  # (K, N, 2) CONTACT_BOUNDARIES indices of an edge / corner contact, -1: none

    def __iter__(self):  # (x, status, iterations), as solve_grid returned before
        return iter((self.x, self.status, self.iterations))


#: solve_grid runs up to this many error sets in one thread (a mesh study, a backlash: one set)
SERIAL_MAX_SETS = 32


def solve_grid(geom, flank, errors, phi_grid, backend="auto", options: SolverOptions = DEFAULT_OPTIONS):
    """Pair 0 for error sets (K, 5) x pinion angles (N,), in any order.

    Both backends run the same solver core.  Error sets whose every point failed (the
    homotopy from the aligned contact lost track) are solved again with 4x, then 16x, as many
    homotopy steps.
    """
    errors = np.ascontiguousarray(np.atleast_2d(errors_array(errors)), dtype=float)
    sol = _solve_grid_once(geom, flank, errors, phi_grid, backend, options, options.homotopy_steps)
    for factor in (4, 16):
        lost = np.nonzero((sol.status == Status.FAILED).all(axis=1))[0]
        if lost.size == 0:
            break
        again = _solve_grid_once(geom, flank, errors[lost], phi_grid, backend, options,
                                 options.homotopy_steps * factor)
        for name in ("x", "status", "iterations", "boundary", "active"):
            getattr(sol, name)[lost] = getattr(again, name)
    return sol


def _solve_grid_once(geom, flank, errors, phi_grid, backend, options, homotopy_steps):
    ref = reference_contact(geom, flank)
    phi_grid = np.asarray(phi_grid, dtype=float)
    order = np.argsort(phi_grid, kind="stable")
    grid = np.ascontiguousarray(phi_grid[order])
    K, N = errors.shape[0], grid.shape[0]
    x = np.empty((K, N, len(tca_kernels.UNKNOWNS)))
    code = np.empty((K, N), dtype=np.int64)
    iters = np.empty((K, N), dtype=np.int64)
    boundary = np.empty((K, N), dtype=np.int64)
    active = np.empty((K, N, 2), dtype=np.int64)
    core = _core(backend, announce=True)
    cover = patch_cover.patch_cover(geom, "pinion", flank, options.patch_tol_mm).cells
    # a parallel call costs ~8 ms to start its threads (docs/performance.md): few error sets run serially
    solve_paths = core.solve_paths if K > SERIAL_MAX_SETS else core.solve_paths_serial
    solve_paths(geom.problem(flank), geom.pinion.blank(), geom.gear.blank(), cover, np.ascontiguousarray(ref.x),
                     ref.pinion_angle, errors, grid, geom.gear.working_pitch_radius_mm,
                     newton_tolerance(geom, options.tol_mm), options.max_iter, homotopy_steps, options.patch_tol_mm,
                     first_touch_sign(geom, flank), x, code, iters, boundary, active)
    if np.array_equal(order, np.arange(N)):  # an ascending grid (the sweep's): no copies back
        return GridSolution(x, code, iters, boundary, active)
    inv = np.empty_like(order)
    inv[order] = np.arange(N)
    return GridSolution(x[:, inv], code[:, inv], iters[:, inv], boundary[:, inv], active[:, inv])


def contact_boundary_names(active):
    """Names of the active boundaries (..., 2) of solved contacts: None for surface contact, else
    e.g. "pinion tip" (edge contact) or "corner: pinion tip / gear heel"."""
    names = tca_kernels.CONTACT_BOUNDARIES
    a = np.asarray(active).reshape(-1, 2)
    out = [None if i < 0 else names[i] if j < 0 else f"corner: {names[i]} / {names[j]}" for i, j in a]
    return out


def tangent(geom, flank, x, phi1, errors):
    """dx/dphi1 and dx/derrors at solutions x (implicit function theorem, exact Jacobians)."""
    s = evaluate(geom, flank, x, phi1, errors)
    dphi = -np.linalg.solve(s.residual_D_unknowns, s.residual_D_pinion_angle[..., None])[..., 0]
    derr = -np.linalg.solve(s.residual_D_unknowns, s.residual_D_errors)
    return dphi, derr


# --------------------------------------------------------------------------------------------
# path over the mesh
# --------------------------------------------------------------------------------------------
@dataclass
class FlankResult:
    """One flank over the mesh: pairs x positions, flattened in pair-major order."""

    flank: str
    pinion_angle: np.ndarray
    gear_angle: np.ndarray
    transmission_error: np.ndarray
    pinion_contact: np.ndarray  # (n, 3) in S1
    gear_contact: np.ndarray  # (n, 3) in S2
    status: list
    tooth_pair: np.ndarray
    active: np.ndarray  # carries the contact (envelope of all pairs) at its pinion angle
    iterations: np.ndarray
    nearest_boundary: list
    te_peak_to_peak: float  # rad, over the active points; nan if none
    unknowns: np.ndarray = None  # (n, 5) pair 0's (l1, u1, l2, u2, phi'_2) as solved, for every point
    contact_ellipse: object = None  # contact_ellipse.ContactEllipses, when attached (contact_ellipse.attach)
    #: per point: None (surface contact or no contact), else the boundary of an edge contact
    #: ("pinion tip") or the two of a corner contact ("corner: pinion tip / gear heel")
    contact_boundary: list = None
    #: per point: the contact's smallest margin (mm) to the boundaries that do not carry it; nan without contact
    boundary_margin_mm: np.ndarray = None

    @property
    def newton_iterations_mean(self) -> float | None:
        """Mean Newton iterations of the points that converged (None if none did)."""
        solved = np.array([st != Status.FAILED.label for st in self.status])
        return float(np.mean(self.iterations[solved])) if solved.any() else None

    def to_json_dict(self):
        nan_to_none = lambda a: [None if not np.isfinite(v) else float(v) for v in a]  # noqa: E731
        pts = lambda P: [None if not np.all(np.isfinite(p)) else [float(c) for c in p] for p in P]  # noqa: E731
        return {
            "pinion_angle_rad": [float(v) for v in self.pinion_angle],
            "gear_angle_rad": nan_to_none(self.gear_angle),
            "transmission_error_rad": nan_to_none(self.transmission_error),
            "pinion_contact_mm": pts(self.pinion_contact),
            "gear_contact_mm": pts(self.gear_contact),
            "status": list(self.status),
            "tooth_pair": [int(k) for k in self.tooth_pair],
            "active": [bool(a) for a in self.active],
            "nearest_boundary": list(self.nearest_boundary),
            **(self.contact_ellipse.to_json_dict() if self.contact_ellipse is not None else {}),
            "newton_iterations": [int(k) for k in self.iterations],
            "newton_iterations_mean": self.newton_iterations_mean,
            "contact_boundary": (list(self.contact_boundary) if self.contact_boundary is not None
                                 else [None] * len(self.status)),
            "boundary_margin_mm": (nan_to_none(self.boundary_margin_mm) if self.boundary_margin_mm is not None
                                   else [None] * len(self.status)),
        }


def _rotate_z(P, angle):
    c, s = np.cos(angle), np.sin(angle)
    out = P.copy()
    out[..., 0] = c * P[..., 0] - s * P[..., 1]
    out[..., 1] = s * P[..., 0] + c * P[..., 1]
    return out


def mesh_flank(geom: PairGeometry, flank: str, errors=(0, 0, 0, 0, 0), positions=200, pairs=3,
               options: SolverOptions = DEFAULT_OPTIONS, window_pitches=None, backend="auto"):
    """TCA of one flank over the mesh with neighbouring tooth pairs.

    Pinion angles: ``positions`` points spread over ``window_pitches`` pinion pitches (default:
    ``pairs``) centred on the reference contact; pairs k = -(pairs//2) .. pairs//2.
    """
    e = errors_array(errors).reshape(1, len(ERROR_NAMES))
    ref = reference_contact(geom, flank)
    p1, p2 = geom.pitch_angles
    N1, N2 = geom.pinion.teeth, geom.gear.teeth
    window = (window_pitches or pairs) * p1
    phi1 = ref.pinion_angle + np.linspace(-window / 2, window / 2, positions)
    ks = np.arange(pairs) - pairs // 2
    # pair k at phi1 is pair 0 at phi1 - k p1
    shifted = (phi1[None, :] - ks[:, None] * p1).ravel()
    sol = solve_grid(geom, flank, e, shifted, backend, options)
    x, code, iterations, boundary = sol.x[0], sol.status[0], sol.iterations[0], sol.boundary[0]
    act = sol.active[0]
    names = np.asarray(tca_kernels.CONTACT_BOUNDARIES + ("",))
    nearest = names[np.where(boundary >= 0, boundary, len(names) - 1)]
    kk = np.repeat(ks, positions)
    phi1_all = np.tile(phi1, pairs)
    phi2 = unknowns(x).gear_angle_rad - kk * p2  # gear tooth k is turned by -k p2 relative to tooth 0
    te = phi2 - unknowns(ref.x).gear_angle_rad + (N1 / N2) * (phi1_all - ref.pinion_angle)
    # contact points of pair k, back in place in S1 / S2
    P1, P2 = contact_points(geom, flank, x)
    P1, P2 = _rotate_z(P1, kk * p1), _rotate_z(P2, -kk * p2)
    valid = carries_numbers(code)
    te_v = np.where(valid, te, np.nan)
    P1[~valid] = np.nan
    P2[~valid] = np.nan
    phi2_v = np.where(valid, phi2, np.nan)
    # envelope: the pair that constrains the gear most carries the contact
    sign = first_touch_sign(geom, flank)
    TE = te_v.reshape(pairs, positions)
    with np.errstate(invalid="ignore"):
        if sign > 0:
            env = np.nanmax(np.where(np.isnan(TE), -np.inf, TE), axis=0)
        else:
            env = np.nanmin(np.where(np.isnan(TE), np.inf, TE), axis=0)
    env = np.where(np.isfinite(env), env, np.nan)
    active = (np.abs(TE - env[None, :]) <= 1e-12 + 1e-9 * np.abs(env)[None, :]) & np.isfinite(TE)
    env_ok = env[np.isfinite(env)]
    ptp = float(env_ok.max() - env_ok.min()) if env_ok.size else float("nan")
    with np.errstate(invalid="ignore"):
        M = contact_margins(geom, flank, x)
    rows = np.arange(len(x))
    for c in range(2):
        hit = act[:, c] >= 0
        M[rows[hit], act[hit, c]] = np.inf
    margin = np.where(valid, M.min(axis=-1), np.nan)
    boundary_names = [n if v else None for n, v in zip(contact_boundary_names(act), valid)]
    return FlankResult(flank, phi1_all, phi2_v, te_v, P1, P2, Status.labels(code), kk, active.ravel(), iterations,
                       [str(n) for n in nearest], ptp, x, contact_boundary=boundary_names,
                       boundary_margin_mm=margin)


@functools.lru_cache(maxsize=64)
def first_touch_sign(geom, flank):
    """+1 if a tooth pair's contact is the largest gear angle phi'_2 at which its patches touch,
    -1 if the smallest (the side from which the gear closes the gap, see _gap_sign)."""
    return _gap_sign(geom, flank, reference_contact(geom, flank))


def _gap_sign(geom, flank, ref):
    """+1 if turning the gear by +dphi2 opens the contact (so the contact pair is the max TE)."""
    s = evaluate(geom, flank, ref.x, ref.pinion_angle, np.zeros(len(ERROR_NAMES)))
    # d(R_f1 - R_f2)/dphi2 is the gear-angle column of the position rows; the gap grows along
    # n_f1 when R_f2 moves along +n_f1, i.e. (R_f1 - R_f2) moves along -n_f1
    u = unknowns(ref.x)
    n1 = surface(geom, "pinion", flank, u.pinion_l_mm, u.pinion_u_mm).normal
    c, si = math.cos(ref.pinion_angle), math.sin(ref.pinion_angle)
    nf1 = np.array([c * n1[0] - si * n1[1], si * n1[0] + c * n1[1], n1[2]])
    dgap = -unknowns(s.residual_D_unknowns[:3]).gear_angle_rad @ nf1
    return 1.0 if dgap > 0 else -1.0


@dataclass(frozen=True)
class Backlash:
    """Two-flank circumferential backlash at the gear's working pitch radius.

    ``um`` is the functional backlash: the smallest play over one mesh cycle (one pinion
    pitch), each flank's contact being the tooth pair that constrains the gear most (as for the
    TE).  Conjugate (involute) flanks have the same play at every angle; crowned flanks do not,
    and the gear can only rattle by the smallest.  ``at_reference_um`` is the play at the left
    flank's reference pinion angle, ``max_um`` the largest play over the cycle.  ``status`` is
    "ok" when both flanks touch on their active flanks at some angle of the cycle (then the
    numbers are set: positive play, negative interference); otherwise the status of the flank
    contact that is missing ("outside" or "failed") and the numbers are None.
    """

    um: float | None
    status: str
    reason: str = ""
    at_reference_um: float | None = None
    max_um: float | None = None


def _raw_play(geom, errors, backend, options):
    """(play in rad before removing whole pitches, statuses of the left and right contacts)."""
    e = errors_array(errors).reshape(1, len(ERROR_NAMES))
    phi1 = reference_contact(geom, "left").pinion_angle
    angles, signs, codes = {}, {}, {}
    for fl in FLANKS:
        sol = solve_grid(geom, fl, e, np.array([phi1]), backend, options)
        angles[fl] = unknowns(sol.x[0, 0]).gear_angle_rad
        codes[fl] = Status(int(sol.status[0, 0]))
        signs[fl] = first_touch_sign(geom, fl)
    if signs["left"] == signs["right"]:
        raise RuntimeError("both flanks open in the same direction: flank orientation is inconsistent")
    # the left contact lets the gear move toward sign_left; the right contact stops it
    return (angles["right"] - angles["left"]) * signs["left"], codes


@functools.lru_cache(maxsize=64)
def _whole_pitches(geom, backend, options):
    """How many whole gear pitches separate the left and right pair-0 contacts: the aligned
    pair is backlash-free by Eq 27, so its raw play is that many pitches (to round-off)."""
    play, codes = _raw_play(geom, np.zeros(len(ERROR_NAMES)), backend, options)
    if any(c == Status.FAILED for c in codes.values()):
        return None
    return round(play / geom.pitch_angles[1])


BACKLASH_POSITIONS = 48  # pinion angles over one pitch, then two local refinements of the minimum
BACKLASH_PAIRS = 5


def _flank_limit(geom, flank, errors, phi1, backend, options):
    """Gear angle at which the flank's binding tooth pair touches at each pinion angle (rad;
    nan where no pair touches on the flanks), and the status of the pair-0 contact at phi1[0]."""
    p1, p2 = geom.pitch_angles
    ks = np.arange(BACKLASH_PAIRS) - BACKLASH_PAIRS // 2
    sol = solve_grid(geom, flank, errors, (phi1[None, :] - ks[:, None] * p1).ravel(), backend, options)
    phi2 = (unknowns(sol.x[0]).gear_angle_rad - np.repeat(ks, phi1.size) * p2).reshape(ks.size, phi1.size)
    phi2 = np.where(carries_numbers(sol.status[0]).reshape(phi2.shape), phi2, np.nan)
    if first_touch_sign(geom, flank) > 0:
        limit = np.where(np.isnan(phi2), -np.inf, phi2).max(axis=0)
    else:
        limit = np.where(np.isnan(phi2), np.inf, phi2).min(axis=0)
    return np.where(np.isfinite(limit), limit, np.nan), Status(int(sol.status[0, BACKLASH_PAIRS // 2 * phi1.size]))


def _play(geom, errors, phi1, whole, backend, options):
    """Play (rad) at the pinion angles phi1 and the reference statuses of the two flanks."""
    limits, codes = {}, {}
    for fl in FLANKS:
        limits[fl], codes[fl] = _flank_limit(geom, fl, errors, phi1, backend, options)
    sign = first_touch_sign(geom, "left")
    return (limits["right"] - limits["left"]) * sign - whole * geom.pitch_angles[1], codes


def backlash(geom: PairGeometry, errors=(0, 0, 0, 0, 0), backend="auto", options=DEFAULT_OPTIONS) -> Backlash:
    """Functional circumferential backlash (um) at the gear's working pitch radius, from a
    two-flank TCA over one mesh cycle.

    At each pinion angle the left and right flanks' binding contacts bound the gear angle; the
    play is the gear's free angle between them, less the whole pitches between the two pair-0
    contacts of the aligned pair, times r_w2.  The backlash is the smallest play over one
    pinion pitch (48 angles, the minimum refined twice on a finer grid); never reduced modulo
    the pitch.  Positive: play; negative: the flanks would interfere.
    """
    k = _whole_pitches(geom, backend, options)
    if k is None:
        return Backlash(None, Status.FAILED.label, "the aligned pair has no two-flank contact")
    e = errors_array(errors).reshape(1, len(ERROR_NAMES))
    start = reference_contact(geom, "left").pinion_angle
    step = geom.pitch_angles[0] / BACKLASH_POSITIONS
    phi1 = start + step * np.arange(BACKLASH_POSITIONS)
    play, codes = _play(geom, e, phi1, k, backend, options)
    at_reference = play[0]
    if not np.isfinite(play).any():
        fl = next((f for f in FLANKS if not carries_numbers(codes[f])), "left")
        why = ("the solver did not converge" if codes[fl] == Status.FAILED else
               "the tangency lies off the flank over the whole mesh cycle")
        return Backlash(None, codes[fl].label, f"{fl} flank: {why}")
    smallest, largest = np.nanmin(play), np.nanmax(play)
    centre = phi1[np.nanargmin(play)]
    for _ in range(2):  # the minimum sits at a tooth-pair transfer (a kink): refine about it
        fine = centre + np.linspace(-step, step, 17)
        play, _ = _play(geom, e, fine, k, backend, options)
        if np.isfinite(play).any() and np.nanmin(play) < smallest:
            smallest, centre = np.nanmin(play), fine[np.nanargmin(play)]
        step /= 8
    r_um = geom.gear.working_pitch_radius_mm * 1e3
    pitch_um = geom.pitch_angles[1] * r_um
    if max(abs(smallest), abs(largest)) * r_um > pitch_um:
        # two flanks that bound one tooth space cannot be a circular pitch apart: the contacts found
        # (e.g. edges of far misaligned teeth) do not measure a play
        return Backlash(None, Status.OUTSIDE.label,
                        f"the two flank contacts are {smallest * r_um:.0f} um apart, more than a circular pitch "
                        f"({pitch_um:.0f} um): they bound no single tooth space")
    return Backlash(float(smallest * r_um), Status.OK.label,
                    at_reference_um=float(at_reference * r_um) if np.isfinite(at_reference) else None,
                    max_um=float(largest * r_um))


@dataclass
class TCAResult:
    geometry: PairGeometry
    errors: np.ndarray
    flanks: dict = field(default_factory=dict)
    backlash: Backlash | None = None
    notes: list = field(default_factory=list)
    approach_mm: float | None = None  # elastic approach of the contact ellipses, when attached

    @property
    def backlash_um(self):
        return None if self.backlash is None else self.backlash.um

    def to_json_dict(self):
        out = {
            "errors": assembly_errors.from_layout(self.errors),
            "flanks": {k: v.to_json_dict() for k, v in self.flanks.items()},
            "te_peak_to_peak_urad": {k: (None if not np.isfinite(v.te_peak_to_peak) else v.te_peak_to_peak * 1e6)
                                     for k, v in self.flanks.items()},
        }
        if self.backlash is not None:
            out["backlash_um"] = self.backlash.um
            out["backlash_status"] = self.backlash.status
            out["backlash_at_reference_um"] = self.backlash.at_reference_um
            out["backlash_max_um"] = self.backlash.max_um
        if self.approach_mm is not None:
            out["approach_mm"] = self.approach_mm
        out["newton_iterations_mean"] = {k: v.newton_iterations_mean for k, v in self.flanks.items()}
        out["notes"] = list(self.notes)
        if self.backlash is not None and self.backlash.um is None:
            out["notes"].append(f"backlash not measured ({self.backlash.status}): {self.backlash.reason}")
        return out


def pitch_point_notes(geom: PairGeometry, flank: str, patch_tol_mm=DEFAULT_OPTIONS.patch_tol_mm):
    """Why an aligned flank may show no contact: the pitch point P lies off a member's active flank."""
    ref = reference_contact(geom, flank)
    margin, which = boundary_margins(geom, flank, ref.x[None])
    if margin[0] >= -patch_tol_mm:
        return []
    return [f"{flank} flank: the pitch point P lies {-margin[0]:.3f} mm beyond the {which[0]} boundary, so the "
            f"aligned contact near P is off the active flank (the working pitch circle is outside the active "
            f"profile: check the profile shifts and the working pressure angle of the design)"]


def analyze(geom: PairGeometry, errors=(0, 0, 0, 0, 0), flanks=FLANKS, positions=200, pairs=3,
            options: SolverOptions = DEFAULT_OPTIONS, backend="auto"):
    """TCA of the given flanks over the mesh; the two-flank backlash when both flanks are solved."""
    for fl in flanks:
        _check_flank(fl)
    e = errors_array(errors)
    res = TCAResult(geom, e)
    for fl in flanks:
        res.flanks[fl] = mesh_flank(geom, fl, e, positions=positions, pairs=pairs, options=options, backend=backend)
        res.notes += pitch_point_notes(geom, fl, options.patch_tol_mm)
    if set(flanks) == set(FLANKS):
        res.backlash = backlash(geom, e, backend=backend, options=options)
    return res


def sensitivity(geom: PairGeometry, flank: str, errors=(0, 0, 0, 0, 0), pinion_angle=None, backend="auto"):
    """Exact first-order derivatives at one mesh position (implicit function theorem).

    Returns dict with 'unknowns_D_errors' (5x5: d(UNKNOWNS)/d(errors)),
    'pinion_contact_D_errors' (3x5, mm per error unit), 'gear_contact_D_errors' (3x5) and
    'gear_angle_D_errors' (5,), at the contact for the given errors and pinion angle
    (default: the reference pinion angle).  They are the derivatives of the surface contact
    (Eq 38): 'converged' is False unless the point is a surface contact ('ok'), 'status' says
    what it is.
    """
    e = errors_array(errors).reshape(1, len(ERROR_NAMES))
    ref = reference_contact(geom, flank)
    phi1 = ref.pinion_angle if pinion_angle is None else pinion_angle
    sol = solve_grid(geom, flank, e, np.array([phi1]), backend)
    x = sol.x[0, 0]
    _, derr = tangent(geom, flank, x[None], np.array([phi1]), e)
    derr = derr[0]
    u = unknowns(x)
    J1 = surface_jacobian(geom, "pinion", flank, u.pinion_l_mm, u.pinion_u_mm)
    J2 = surface_jacobian(geom, "gear", flank, u.gear_l_mm, u.gear_u_mm)
    d = unknowns(derr.T)  # rows of d(unknowns)/d(errors), by name
    return {
        "x": x, "pinion_angle": phi1, "converged": bool(sol.status[0, 0] == Status.OK),
        "status": Status(int(sol.status[0, 0])).label,
        "unknowns_D_errors": derr,
        "pinion_contact_D_errors": J1 @ np.stack([d.pinion_l_mm, d.pinion_u_mm]),
        "gear_contact_D_errors": J2 @ np.stack([d.gear_l_mm, d.gear_u_mm]),
        "gear_angle_D_errors": d.gear_angle_rad,
    }

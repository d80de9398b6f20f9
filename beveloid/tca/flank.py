"""One flank over the mesh: neighbouring tooth pairs, their TE and the envelope that carries it."""
from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from .. import mesh
from ..generated import tca_kernels
from ..geometry import PairGeometry
from ..result import Frozen
from ..solver import Solver
from ..solver.options import DEFAULT_OPTIONS
from ..status import Status, carries_numbers
from .contact import (ERROR_NAMES, contact_boundary_names, contact_margins, contact_points,
                      errors_array, rotate_z, unknowns)
from .grid import solve_grid
from .reference import first_touch_sign, reference_contact


@dataclass(frozen=True)
class FlankResult(Frozen):
    """One flank over the mesh: pairs x positions, flattened in pair-major order (frozen: its arrays
    read-only, its sequences tuples)."""

    flank: str
    pinion_angle: np.ndarray
    gear_angle: np.ndarray
    transmission_error: np.ndarray
    pinion_contact: np.ndarray  # (n, 3) in S1
    gear_contact: np.ndarray  # (n, 3) in S2
    status: tuple
    tooth_pair: np.ndarray
    active: np.ndarray  # carries the contact (envelope of all pairs) at its pinion angle
    iterations: np.ndarray
    nearest_boundary: tuple
    #: rad, of the envelope where it is complete (te_envelope_complete); nan with fewer than two such
    #: positions (one position, or too few pairs for the contact ratio)
    te_peak_to_peak: float
    unknowns: np.ndarray = None  # (n, 5) pair 0's (l1, u1, l2, u2, phi'_2) as solved, for every point
    contact_ellipse: object = None  # contact_ellipse.ContactEllipses, when computed (tca.Options.approach_mm)
    #: per point: None (surface contact or no contact), else the boundary of an edge contact
    #: ("pinion tip") or the two of a corner contact ("corner: pinion tip / gear heel")
    contact_boundary: tuple = None
    #: per point: the contact's smallest margin (mm) to the boundaries that do not carry it; nan without contact
    boundary_margin_mm: np.ndarray = None
    #: per position: no tooth pair beyond those solved can carry the contact there (mesh.envelope_complete)
    te_envelope_complete: np.ndarray = None

    @property
    def positions(self) -> int:
        """Pinion positions (the points are pairs x positions)."""
        return len(self.status) // len(np.unique(self.tooth_pair))

    @property
    def newton_iterations_mean(self) -> float | None:
        """Mean Newton iterations of the points that converged (None if none did)."""
        solved = np.array([st != Status.FAILED.label for st in self.status])
        return float(np.mean(self.iterations[solved])) if solved.any() else None

    def to_json(self) -> dict:
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
            **(self.contact_ellipse.to_json() if self.contact_ellipse is not None else {}),
            "newton_iterations": [int(k) for k in self.iterations],
            "newton_iterations_mean": self.newton_iterations_mean,
            "contact_boundary": (list(self.contact_boundary) if self.contact_boundary is not None
                                 else [None] * len(self.status)),
            "boundary_margin_mm": (nan_to_none(self.boundary_margin_mm) if self.boundary_margin_mm is not None
                                   else [None] * len(self.status)),
            "te_envelope_complete": ([bool(c) for c in self.te_envelope_complete]
                                     if self.te_envelope_complete is not None else None),
        }


def mesh_angles(geom, flank, positions, pairs, window_pitches=None, options=DEFAULT_OPTIONS):
    """The pinion angles of a mesh study: ``positions`` points over ``window_pitches`` (default
    ``pairs``) pinion pitches centred on the reference contact (solved with the solver ``options``);
    one position: the reference angle."""
    ref = reference_contact(geom, flank, options)
    if positions == 1:
        return np.array([ref.pinion_angle])
    window = (window_pitches or pairs) * geom.pitch_angles[0]
    return ref.pinion_angle + np.linspace(-window / 2, window / 2, positions)


class MeshPaths(NamedTuple):
    """The rigid mesh of one flank for K error sets (:func:`mesh_paths`): pairs x positions points flattened in
    pair-major order, as :class:`FlankResult`'s."""

    pinion_angle: np.ndarray  # (n,) the pinion angle of each point
    tooth_pair: np.ndarray  # (n,) its pair k
    unknowns: np.ndarray  # (K, n, 5) pair 0's unknowns as solved
    code: np.ndarray  # (K, n) Status codes
    iterations: np.ndarray  # (K, n)
    boundary: np.ndarray  # (K, n) solve_grid's nearest boundary
    contact_active: np.ndarray  # (K, n, 2) solve_grid's active boundaries
    gear_angle: np.ndarray  # (K, n) the gear angle of pair k, nan where the status carries no numbers
    transmission_error: np.ndarray  # (K, n) nan where the status carries no numbers
    active: np.ndarray  # (K, n) carries the contact (the envelope of all pairs) at its pinion angle
    envelope: np.ndarray  # (K, positions) the TE envelope

    def of_set(self, k: int) -> "MeshPaths":
        """Error set k's alone (K = 1); the pinion angles and pairs are every set's."""
        return self._replace(**{f: getattr(self, f)[k:k + 1] for f in self._fields
                                if f not in ("pinion_angle", "tooth_pair")})


def mesh_paths(geom: PairGeometry, flank: str, error_sets, positions=200, pairs=3, window_pitches=None, *,
               solver: Solver | None = None, angles=None) -> MeshPaths:
    """The pinion angles, unknowns, statuses, TE and envelope of :func:`mesh_flank` for each of the error sets
    (K, 5), solved in one call of the solver core (each set's numbers its own: the core solves a set alone);
    without the contact points and margins (the loaded engine's rigid reference reads none of them).
    ``angles``: the pinion angles (rad, ``positions`` of them) instead of :func:`mesh_angles`' (the rating's
    refinement of a maximum between positions)."""
    solver = Solver.of(solver)
    errors = np.ascontiguousarray(np.atleast_2d(errors_array(error_sets)), dtype=float)
    ref = reference_contact(geom, flank, solver.options)
    p1, p2 = geom.pitch_angles
    phi1 = (mesh_angles(geom, flank, positions, pairs, window_pitches, solver.options) if angles is None
            else np.asarray(angles, dtype=float))
    ks, shifted = mesh.pair_angles(phi1, pairs, p1)
    sol = solve_grid(geom, flank, errors, shifted.ravel(), solver=solver)
    kk = np.repeat(ks, positions)
    phi1_all = np.tile(phi1, pairs)
    phi2 = unknowns(sol.x).gear_angle_rad - kk * p2  # gear tooth k is turned by -k p2 relative to tooth 0
    te = mesh.transmission_error(phi2, phi1_all, unknowns(ref.x).gear_angle_rad, ref.pinion_angle,
                                 geom.pinion.teeth / geom.gear.teeth)
    valid = carries_numbers(sol.status)
    te_v = np.where(valid, te, np.nan)
    env, active = zip(*(mesh.envelope(t.reshape(pairs, positions), first_touch_sign(geom, flank)) for t in te_v))
    return MeshPaths(phi1_all, kk, sol.x, sol.status, sol.iterations, sol.boundary, sol.active,
                     np.where(valid, phi2, np.nan), te_v, np.stack(active).reshape(len(errors), -1), np.stack(env))


def mesh_flank(geom: PairGeometry, flank: str, errors=(0, 0, 0, 0, 0), positions=200, pairs=3,
               window_pitches=None, *, solver: Solver | None = None) -> FlankResult:
    """TCA of one flank over the mesh with neighbouring tooth pairs.

    Pinion angles: ``positions`` points spread over ``window_pitches`` pinion pitches (default:
    ``pairs``) centred on the reference contact; pairs k = -(pairs//2) .. pairs//2.
    ``solver``: a :class:`beveloid.solver.Solver` (None: the default), its backend and tolerances.
    """
    solver = Solver.of(solver)
    e = errors_array(errors).reshape(1, len(ERROR_NAMES))
    m = mesh_paths(geom, flank, e, positions, pairs, window_pitches, solver=solver)
    p1, p2 = geom.pitch_angles
    phi1 = m.pinion_angle[:positions]
    x, code, iterations, boundary, act = m.unknowns[0], m.code[0], m.iterations[0], m.boundary[0], m.contact_active[0]
    names = np.asarray(tca_kernels.CONTACT_BOUNDARIES + ("",))
    nearest = names[np.where(boundary >= 0, boundary, len(names) - 1)]
    kk, phi1_all = m.tooth_pair, m.pinion_angle
    valid = carries_numbers(code)
    # contact points of pair k and their boundary margins; a diverged iterate's are not used (NaN
    # below), so its overflow is not news
    with np.errstate(over="ignore", invalid="ignore"):
        P1, P2 = contact_points(geom, flank, x)
        M = contact_margins(geom, flank, x)
    P1, P2 = rotate_z(P1, kk * p1), rotate_z(P2, -kk * p2)  # back in place in S1 / S2
    te_v = m.transmission_error[0]
    P1[~valid] = np.nan
    P2[~valid] = np.nan
    env, active = m.envelope[0], m.active[0].reshape(pairs, positions)
    step = abs(phi1[1] - phi1[0]) if positions > 1 else 0.0
    ks = kk[::positions]
    complete = mesh.envelope_complete(phi1, ks, active, p1, step)
    ptp = mesh.peak_to_peak(env[complete]) if complete.sum() >= 2 else float("nan")
    rows = np.arange(len(x))
    for c in range(2):
        hit = act[:, c] >= 0
        M[rows[hit], act[hit, c]] = np.inf
    margin = np.where(valid, M.min(axis=-1), np.nan)
    boundary_names = [n if v else None for n, v in zip(contact_boundary_names(act), valid)]
    return FlankResult(flank=flank, pinion_angle=phi1_all, gear_angle=m.gear_angle[0], transmission_error=te_v,
                       pinion_contact=P1, gear_contact=P2, status=Status.labels(code), tooth_pair=kk,
                       active=active.ravel(), iterations=iterations, nearest_boundary=[str(n) for n in nearest],
                       te_peak_to_peak=ptp, unknowns=x, contact_boundary=boundary_names,
                       boundary_margin_mm=margin, te_envelope_complete=complete)

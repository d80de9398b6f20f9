"""Two-flank circumferential backlash over one mesh cycle."""
from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from .. import mesh
from ..geometry import PairGeometry
from ..result import Frozen
from ..solver import Solver
from ..status import Status, carries_numbers
from .contact import ERROR_NAMES, FLANKS, errors_array, unknowns
from .grid import solve_grid
from .reference import first_touch_sign, reference_contact


@dataclass(frozen=True)
class Backlash(Frozen):
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


BACKLASH_POSITIONS = 48  # pinion angles over one pitch, then two local refinements of the minimum
BACKLASH_PAIRS = 5


def _raw_play(geom, errors, solver):
    """(play in rad before removing whole pitches, statuses of the left and right contacts)."""
    e = errors_array(errors).reshape(1, len(ERROR_NAMES))
    phi1 = reference_contact(geom, "left", solver.options).pinion_angle
    angles, signs, codes = {}, {}, {}
    for fl in FLANKS:
        sol = solve_grid(geom, fl, e, np.array([phi1]), solver=solver)
        angles[fl] = unknowns(sol.x[0, 0]).gear_angle_rad
        codes[fl] = Status(int(sol.status[0, 0]))
        signs[fl] = first_touch_sign(geom, fl)
    if signs["left"] == signs["right"]:
        # the flanks' reference contacts open the gear the same way: one of them is not a contact of this tooth
        # space (e.g. a root of the flanks' extension far off the face): no play to measure
        return np.nan, {fl: Status.FAILED for fl in FLANKS}
    # the left contact lets the gear move toward sign_left; the right contact stops it
    return (angles["right"] - angles["left"]) * signs["left"], codes


@functools.lru_cache(maxsize=64)
def whole_pitches(geom, solver: Solver):
    """How many whole gear pitches separate the left and right pair-0 contacts: the aligned
    pair is backlash-free by Eq 27, so its raw play is that many pitches (to round-off)."""
    play, codes = _raw_play(geom, np.zeros(len(ERROR_NAMES)), solver)
    if any(c == Status.FAILED for c in codes.values()):
        return None
    return round(play / geom.pitch_angles[1])


def _flank_limit(geom, flank, errors, phi1, solver):
    """Gear angle at which the flank's binding tooth pair touches at each pinion angle (rad;
    nan where no pair touches on the flanks), and the status of the pair-0 contact at phi1[0]."""
    p1, p2 = geom.pitch_angles
    ks, shifted = mesh.pair_angles(phi1, BACKLASH_PAIRS, p1)
    sol = solve_grid(geom, flank, errors, shifted.ravel(), solver=solver)
    phi2 = (unknowns(sol.x[0]).gear_angle_rad - np.repeat(ks, phi1.size) * p2).reshape(ks.size, phi1.size)
    phi2 = np.where(carries_numbers(sol.status[0]).reshape(phi2.shape), phi2, np.nan)
    limit, _ = mesh.envelope(phi2, first_touch_sign(geom, flank))
    return limit, Status(int(sol.status[0, BACKLASH_PAIRS // 2 * phi1.size]))


def _play(geom, errors, phi1, whole, solver):
    """Play (rad) at the pinion angles phi1 and the reference statuses of the two flanks."""
    limits, codes = {}, {}
    for fl in FLANKS:
        limits[fl], codes[fl] = _flank_limit(geom, fl, errors, phi1, solver)
    sign = first_touch_sign(geom, "left")
    return (limits["right"] - limits["left"]) * sign - whole * geom.pitch_angles[1], codes


def backlash(geom: PairGeometry, errors=(0, 0, 0, 0, 0), *, solver: Solver | None = None) -> Backlash:
    """Functional circumferential backlash (um) at the gear's working pitch radius, from a
    two-flank TCA over one mesh cycle.

    At each pinion angle the left and right flanks' binding contacts bound the gear angle; the
    play is the gear's free angle between them, less the whole pitches between the two pair-0
    contacts of the aligned pair, times r_w2.  The backlash is the smallest play over one
    pinion pitch (48 angles, the minimum refined twice on a finer grid); never reduced modulo
    the pitch.  Positive: play; negative: the flanks would interfere.  ``solver``: a
    :class:`beveloid.solver.Solver` (None: the default).
    """
    geom = getattr(geom, "geometry", geom)
    solver = Solver.of(solver)
    k = whole_pitches(geom, solver)
    if k is None:
        return Backlash(None, Status.FAILED.label, "the aligned pair has no two-flank contact")
    e = errors_array(errors).reshape(1, len(ERROR_NAMES))
    start = reference_contact(geom, "left", solver.options).pinion_angle
    step = geom.pitch_angles[0] / BACKLASH_POSITIONS
    phi1 = start + step * np.arange(BACKLASH_POSITIONS)
    play, codes = _play(geom, e, phi1, k, solver)
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
        play, _ = _play(geom, e, fine, k, solver)
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

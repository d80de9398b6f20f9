"""The TE reference (the aligned contact at the pitch point P) and each flank's first-touch sign."""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from ..generated import layouts
from ..geometry import PairGeometry
from ..solver import backends, section
from ..solver.options import DEFAULT_OPTIONS, SolverOptions
from ..solver.records import settings
from .contact import (ERROR_NAMES, NoContactError, boundary_margins, check_flank, evaluate, newton_tolerance,
                      surface, unknowns)


def point_at_radius(geom, which, flank, radius, z):
    """(l, u, polar angle) of the flank point at the given radius in the transverse section z."""
    m = geom.member(which)
    sp = section.point_at_radius(m.tooth_surface, flank, geom.surface_params(which), radius, z,
                                 m.cutter_addendum_mm / math.cos(geom.normal_pressure_angle))
    return float(sp.l_mm), float(sp.u_mm), math.atan2(sp.point[1], sp.point[0])


@dataclass(frozen=True)
class Reference:
    flank: str
    pinion_angle: float
    x: np.ndarray  # tca_kernels.UNKNOWNS at the pitch point, aligned


@functools.lru_cache(maxsize=64)
def reference_contact(geom: PairGeometry, flank: str, options: SolverOptions = DEFAULT_OPTIONS) -> Reference:
    """Contact of the aligned pair at the pitch point P (the TE reference); cached per geometry and
    solver tolerances (``options``: the analysis' ``Solver.options``).

    Solved by the numpy backend of the core whatever the analysis' backend: one point, so no
    compiled code to load, and the same Newton steps (the backends agree to round-off)."""
    check_flank(flank)
    p, g = geom.pinion, geom.gear
    l1, u1, psi1 = point_at_radius(geom, "pinion", flank, p.working_pitch_radius_mm, p.reference_section_offset_mm)
    l2, u2, psi2 = point_at_radius(geom, "gear", flank, g.working_pitch_radius_mm, g.reference_section_offset_mm)
    phi1 = p.pitch_point_angle - psi1
    phi2 = g.pitch_point_angle - psi2
    x0 = np.asarray(layouts.ContactUnknowns(pinion_l_mm=l1, pinion_u_mm=u1, gear_l_mm=l2, gear_u_mm=u2,
                                            gear_angle_rad=phi2), dtype=float)
    opts = options
    st = settings(scale_mm=geom.gear.working_pitch_radius_mm, tol_mm=newton_tolerance(geom, opts.tol_mm),
                  max_iter=opts.max_iter)
    solve = backends.namespace("numpy").solve_point
    x, conv, _, res = solve(geom.problem(flank), x0, phi1, np.zeros(len(ERROR_NAMES)), st)
    if not conv:  # a modification that moves the contact far from P throws Newton off: follow it there
        x, conv, res = _along_the_modification(geom, flank, x0, phi1, st, solve)
        if conv:
            margin, which = boundary_margins(geom, flank, x[None])
            width = max(geom.pinion.face_width_mm, geom.gear.face_width_mm)
            if margin[0] < -width:  # a root of the flanks' extension, not a contact near the flank
                raise NoContactError(
                    f"no contact near the pitch point on the {flank} flank: followed from the unmodified flank,"
                    f" the modification moves it {-margin[0]:.1f} mm beyond the {which[0]} boundary (more than a"
                    " face width): reduce the modification (lead slope, crowning, relief)")
    if not conv:
        raise NoContactError(f"no contact at the pitch point on the {flank} flank (residual {res:.2e} mm)")
    return Reference(flank, phi1, x)


#: the continuation of :func:`_along_the_modification`: its first step in the amplitude and how often a
#: step that Newton does not take is halved
CONTINUATION_STEP, CONTINUATION_HALVINGS = 0.125, 8


def _along_the_modification(geom, flank, x0, phi1, st, solve):
    """The pitch-point contact by continuation in the modification's amplitude (geometry.modifications_scaled
    from 0 to 1, each solve from the last): (x, converged, residual mm).  Unconverged where the pair carries
    no modification or a step halved CONTINUATION_HALVINGS times still fails."""
    e = np.zeros(len(ERROR_NAMES))
    if geom.modifications_scaled(0.0) is geom:
        return x0, False, math.inf
    x, conv, _, res = solve(geom.modifications_scaled(0.0).problem(flank), x0, phi1, e, st)
    t, step, halvings = 0.0, CONTINUATION_STEP, 0
    while conv and t < 1.0:
        nxt = min(1.0, t + step)
        y, ok, _, res = solve(geom.modifications_scaled(nxt).problem(flank), x, phi1, e, st)
        if ok:
            x, t = y, nxt
        elif halvings < CONTINUATION_HALVINGS:
            step, halvings = step / 2, halvings + 1
        else:
            return y, False, res
    return x, conv, res


@functools.lru_cache(maxsize=64)
def first_touch_sign(geom, flank):
    """+1 if a tooth pair's contact is the largest gear angle phi'_2 at which its patches touch,
    -1 if the smallest (the side from which the gear closes the gap, see gap_sign)."""
    return gap_sign(geom, flank, reference_contact(geom, flank))


def gap_sign(geom, flank, ref):
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


def pitch_point_notes(geom: PairGeometry, flank: str, options: SolverOptions = DEFAULT_OPTIONS):
    """Why an aligned flank may show no contact: the pitch point P lies off a member's active flank."""
    ref = reference_contact(geom, flank, options)
    margin, which = boundary_margins(geom, flank, ref.x[None])
    if margin[0] >= -options.patch_tol_mm:
        return []
    return [f"{flank} flank: the pitch point P lies {-margin[0]:.3f} mm beyond the {which[0]} boundary, so the "
            f"aligned contact near P is off the active flank (the working pitch circle is outside the active "
            f"profile: check the profile shifts and the working pressure angle of the design)"]

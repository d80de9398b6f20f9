"""Chords of the contact ellipses' major axes inside both flanks, one point at a time: the one
chord search, on either backend (:mod:`beveloid.contact_ellipse` builds its request).

From the contact P0 (S_f) along the tangent direction v (in the basis E of the tangent plane),
each member's flank point whose tangent-plane coordinates about P0 are ``s v`` is found by Newton
in (l, u) from the previous one; ``samples`` (fractions of the cap, ascending) find the first
point outside the member's blank (its smallest margin below ``min(margin at P0, 0) - 1e-9``) and
``bisections`` halvings place the boundary.  The chord is the nearer boundary of the two members,
at most the cap.
"""
import math
import typing

import numpy as np

from ..generated.tca_kernels_scalar import blank_margins_point, surface_jet_point

#: how far outside its blank an 'edge' contact may sit and still start a chord [mm]
CHORD_SLACK_MM = 1e-9
#: Newton iterations of _tangent_point: from the tangency, then from the previous point along the chord
TANGENT_ITERATIONS_START = 8
TANGENT_ITERATIONS_STEP = 4


class ChordMember(typing.NamedTuple):
    """One member's flank as the chord search reads it."""

    model: int
    flank: int
    params: np.ndarray  # its surface parameters
    blank: np.ndarray  # its layouts.FlankBlank


class ChordFrame(typing.NamedTuple):
    """One contact of one member: its placement in S_f and the tangent plane there."""

    rotation: np.ndarray  # (3, 3)
    translation: np.ndarray  # (3,)
    origin: np.ndarray  # (3,) the contact P0 in S_f
    basis: np.ndarray  # (2, 3) the tangent plane's basis E


class ChordWork(typing.NamedTuple):
    """Work arrays of the chord search (the surface and margin kernels' outputs)."""

    point: np.ndarray  # (3,)
    normal: np.ndarray  # (3,)
    point_D_lu: np.ndarray  # (3, 2)
    normal_D_lu: np.ndarray  # (3, 2)
    margins: np.ndarray  # (4,)
    margins_D_point: np.ndarray  # (4, 3)
    margins_D_l: np.ndarray  # (4,)


def _tangent_point(member, frame, tx, ty, l, u, iters, work):
    """(l, u) of the flank point whose tangent-plane coordinates about frame.origin are (tx, ty);
    Newton from (l, u)."""
    model, flank, params = member.model, member.flank, member.params
    rot, trans, p0, basis = frame.rotation, frame.translation, frame.origin, frame.basis
    point, point_d = work.point, work.point_D_lu
    # the basis and p0 in the member frame: E L and L^T (p0 - t)
    e00 = basis[0, 0] * rot[0, 0] + basis[0, 1] * rot[1, 0] + basis[0, 2] * rot[2, 0]
    e01 = basis[0, 0] * rot[0, 1] + basis[0, 1] * rot[1, 1] + basis[0, 2] * rot[2, 1]
    e02 = basis[0, 0] * rot[0, 2] + basis[0, 1] * rot[1, 2] + basis[0, 2] * rot[2, 2]
    e10 = basis[1, 0] * rot[0, 0] + basis[1, 1] * rot[1, 0] + basis[1, 2] * rot[2, 0]
    e11 = basis[1, 0] * rot[0, 1] + basis[1, 1] * rot[1, 1] + basis[1, 2] * rot[2, 1]
    e12 = basis[1, 0] * rot[0, 2] + basis[1, 1] * rot[1, 2] + basis[1, 2] * rot[2, 2]
    d0, d1, d2 = p0[0] - trans[0], p0[1] - trans[1], p0[2] - trans[2]
    q0 = rot[0, 0] * d0 + rot[1, 0] * d1 + rot[2, 0] * d2
    q1 = rot[0, 1] * d0 + rot[1, 1] * d1 + rot[2, 1] * d2
    q2 = rot[0, 2] * d0 + rot[1, 2] * d1 + rot[2, 2] * d2
    for _ in range(iters):
        surface_jet_point(model, flank, l, u, params, point, work.normal, point_d, work.normal_D_lu)
        w0, w1, w2 = point[0] - q0, point[1] - q1, point[2] - q2
        r0 = e00 * w0 + e01 * w1 + e02 * w2 - tx
        r1 = e10 * w0 + e11 * w1 + e12 * w2 - ty
        j00 = e00 * point_d[0, 0] + e01 * point_d[1, 0] + e02 * point_d[2, 0]
        j01 = e00 * point_d[0, 1] + e01 * point_d[1, 1] + e02 * point_d[2, 1]
        j10 = e10 * point_d[0, 0] + e11 * point_d[1, 0] + e12 * point_d[2, 0]
        j11 = e10 * point_d[0, 1] + e11 * point_d[1, 1] + e12 * point_d[2, 1]
        det = j00 * j11 - j01 * j10
        step_l = (-r0 * j11 + r1 * j01) / det if det != 0.0 else 0.0
        step_u = (-r1 * j00 + r0 * j10) / det if det != 0.0 else 0.0
        l += step_l if math.isfinite(step_l) else 0.0
        u += step_u if math.isfinite(step_u) else 0.0
    return l, u


def _margin_at(member, l, u, l_margin, work):
    """The smallest of the member's blank margins (NaN if any is) at the flank point (l, u),
    the form limit taken at ``l_margin``."""
    margins = work.margins
    # the jet, not surface_point: the solver core compiles the jets, so the chords compile no other
    # surface function (surface_point of each model and flank: 6 s of a first run's compile)
    surface_jet_point(member.model, member.flank, l, u, member.params, work.point, work.normal, work.point_D_lu,
                      work.normal_D_lu)
    blank_margins_point(work.point, l_margin, member.blank, margins, work.margins_D_point, work.margins_D_l)
    smallest = margins[0]
    for k in range(1, margins.shape[0]):
        if margins[k] < smallest or margins[k] != margins[k]:
            smallest = margins[k]
    return smallest


def ellipse_chords(problem, request, out):
    """Writes out[i]: the chord from contact i of the :class:`records.ChordRequest` ``request``
    along ``directions[i]`` (n, 2) in its tangent basis ``bases[i]`` (n, 2, 3) inside both
    members' blanks (of the :class:`records.Problem`), at most ``caps[i]``.  Per member m (0
    pinion, 1 gear): ``rotations[m]`` (n, 3, 3) and ``translations[m]`` (n, 3) place it in S_f,
    ``start_lu[m]`` (n, 2) is its (l, u) at the contact."""
    work = ChordWork(point=np.empty(3), normal=np.empty(3), point_D_lu=np.empty((3, 2)),
                     normal_D_lu=np.empty((3, 2)), margins=np.empty(4),
                     margins_D_point=np.empty((4, 3)), margins_D_l=np.empty(4))
    samples, bisections, directions = request.samples, request.bisections, request.directions
    for i in range(request.points.shape[0]):
        cap = request.caps[i]
        best = cap
        vx, vy = directions[i, 0], directions[i, 1]
        for m in range(2):
            if m == 0:
                member = ChordMember(model=problem.pinion_model, flank=problem.flank, params=problem.pinion_params,
                                     blank=problem.pinion_blank)
            else:
                member = ChordMember(model=problem.gear_model, flank=problem.flank, params=problem.gear_params,
                                     blank=problem.gear_blank)
            frame = ChordFrame(rotation=request.rotations[m, i], translation=request.translations[m, i],
                               origin=request.points[i], basis=request.bases[i])
            l0, u0 = request.start_lu[m, i, 0], request.start_lu[m, i, 1]
            # the iteration counts as int64 values, not literals: numba compiled _tangent_point once per
            # literal count (Literal[int](8), Literal[int](4))
            l, u = _tangent_point(member, frame, 0.0, 0.0, l0, u0, np.int64(TANGENT_ITERATIONS_START), work)
            iterations = np.int64(TANGENT_ITERATIONS_STEP)
            start = _margin_at(member, l, u, l0, work)
            threshold = min(start, 0.0) - CHORD_SLACK_MM
            s_lo, s_hi, found = 0.0, cap, False
            l, u = l0, u0
            lo_l, lo_u = l0, u0
            for k in range(samples.shape[0]):
                s = samples[k] * cap
                l, u = _tangent_point(member, frame, s * vx, s * vy, l, u, iterations, work)
                if _margin_at(member, l, u, l, work) < threshold:
                    s_hi, found = s, True
                    break
                s_lo, lo_l, lo_u = s, l, u
            if found:
                lo, hi = s_lo, s_hi
                for _ in range(bisections):
                    mid = 0.5 * (lo + hi)
                    l2, u2 = _tangent_point(member, frame, mid * vx, mid * vy, lo_l, lo_u, iterations, work)
                    if _margin_at(member, l2, u2, l2, work) >= threshold:
                        lo, lo_l, lo_u = mid, l2, u2
                    else:
                        hi = mid
                best = min(best, lo)
        out[i] = best

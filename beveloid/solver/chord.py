"""Chords of the contact ellipses' major axes inside both flanks, one point at a time (the
compiled twin of the vectorised search in :mod:`beveloid.contact_ellipse`; the same steps in the
same order, so the two give the same chords to round-off).

From the contact P0 (S_f) along the tangent direction v (in the basis E of the tangent plane),
each member's flank point whose tangent-plane coordinates about P0 are ``s v`` is found by Newton
in (l, u) from the previous one; ``samples`` (fractions of the cap, ascending) find the first
point outside the member's blank (its smallest margin below ``min(margin at P0, 0) - 1e-9``) and
``bisections`` halvings place the boundary.  The chord is the nearer boundary of the two members,
at most the cap.
"""
import math

import numpy as np

from ..generated.tca_kernels_scalar import blank_margins_point, surface_jet_point, surface_point

#: how far outside its blank an 'edge' contact may sit and still start a chord [mm]
CHORD_SLACK_MM = 1e-9


def _tangent_point(model, flank, params, rot, trans, p0, basis, tx, ty, l, u, iters, jet):
    """(l, u) of the flank point whose tangent-plane coordinates about p0 are (tx, ty); Newton
    from (l, u).  ``jet``: the surface_jet_point outputs (point, normal, point_D_lu, normal_D_lu)."""
    point, normal, point_d, normal_d = jet
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
        surface_jet_point(model, flank, l, u, params, point, normal, point_d, normal_d)
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


def _margin_at(model, flank, params, blank, l, u, l_margin, point, normal, roll, margins, margins_d_point, margins_d_l):
    """The smallest of the member's blank margins (NaN if any is) at the flank point (l, u),
    the form limit taken at ``l_margin``."""
    surface_point(model, flank, l, u, params, point, normal, roll)
    blank_margins_point(point, l_margin, blank, margins, margins_d_point, margins_d_l)
    smallest = margins[0]
    for k in range(1, margins.shape[0]):
        if margins[k] < smallest or margins[k] != margins[k]:
            smallest = margins[k]
    return smallest


def ellipse_chords(models, flank, pinion_params, gear_params, pinion_blank, gear_blank, rotations, translations,
                   start_lu, points, bases, directions, caps, samples, bisections, out):
    """Writes out[i]: the chord from contact i along ``directions[i]`` (n, 2) in its tangent basis
    ``bases[i]`` (n, 2, 3) inside both members' blanks, at most ``caps[i]``.  Per member m (0
    pinion, 1 gear): ``rotations[m]`` (n, 3, 3) and ``translations[m]`` (n, 3) place it in S_f,
    ``start_lu[m]`` (n, 2) is its (l, u) at the contact, ``models[m]`` its surface model."""
    point, normal, point_d, normal_d = np.empty(3), np.empty(3), np.empty((3, 2)), np.empty((3, 2))
    jet = (point, normal, point_d, normal_d)
    roll, margins, margins_d_point, margins_d_l = np.empty(1), np.empty(4), np.empty((4, 3)), np.empty(4)
    for i in range(points.shape[0]):
        cap = caps[i]
        best = cap
        vx, vy = directions[i, 0], directions[i, 1]
        for m in range(2):
            params = pinion_params if m == 0 else gear_params
            blank = pinion_blank if m == 0 else gear_blank
            model, rot, trans, p0, basis = models[m], rotations[m, i], translations[m, i], points[i], bases[i]
            l0, u0 = start_lu[m, i, 0], start_lu[m, i, 1]
            l, u = _tangent_point(model, flank, params, rot, trans, p0, basis, 0.0, 0.0, l0, u0, 8, jet)
            start = _margin_at(model, flank, params, blank, l, u, l0, point, normal, roll, margins, margins_d_point,
                               margins_d_l)
            threshold = min(start, 0.0) - CHORD_SLACK_MM
            s_lo, s_hi, found = 0.0, cap, False
            l, u = l0, u0
            lo_l, lo_u = l0, u0
            for k in range(samples.shape[0]):
                s = samples[k] * cap
                l, u = _tangent_point(model, flank, params, rot, trans, p0, basis, s * vx, s * vy, l, u, 4, jet)
                if _margin_at(model, flank, params, blank, l, u, l, point, normal, roll, margins, margins_d_point,
                              margins_d_l) < threshold:
                    s_hi, found = s, True
                    break
                s_lo, lo_l, lo_u = s, l, u
            if found:
                lo, hi = s_lo, s_hi
                for _ in range(bisections):
                    mid = 0.5 * (lo + hi)
                    l2, u2 = _tangent_point(model, flank, params, rot, trans, p0, basis, mid * vx, mid * vy, lo_l, lo_u,
                                            4, jet)
                    if _margin_at(model, flank, params, blank, l2, u2, l2, point, normal, roll, margins,
                                  margins_d_point, margins_d_l) >= threshold:
                        lo, lo_l, lo_u = mid, l2, u2
                    else:
                        hi = mid
                best = min(best, lo)
        out[i] = best

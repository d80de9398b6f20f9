"""Points of the generated tooth in a transverse section: the flank (generated surface kernels) and
the root fillet (generated root-fillet kernels), found by Newton on their jets.

``flank_in_section(geometry, member, flank, z, l)``: the flank points of rack parameters l in the
section z (S_i); ``fillet_in_section(geometry, member, flank, z, psi)`` likewise for the fillet;
``flank_at_radius(geometry, member, flank, z, radius)``: the flank point at a radius of the
section; ``undercut_top(...)``: where the fillet cuts the flank in a section (the top of an undercut).
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..solver.section import point_at_radius
from . import fillet as fillet_kernels

_TOL = 1e-12  # mm
_MAX_ITER = 40


class NoSolution(RuntimeError):
    """Newton did not converge."""


def _solve_u(jet, p, z, u0):
    """Solve point_z(p, u) = z for u, elementwise (jet(p, u) -> point, point_D)."""
    u = np.array(np.broadcast_to(np.asarray(u0, dtype=float), np.broadcast(p, z, u0).shape))
    for _ in range(_MAX_ITER):
        j = jet(p, u)
        f = j[0][..., 2] - z
        u = u - f / j[2][..., 2, 1]
        if np.all(np.abs(f) < _TOL):
            return u
    raise NoSolution("no point of the surface in this section")


def flank_in_section(geometry, member, flank, z, l, u0=0.0):
    """(points (..., 3), u) of the flank at rack parameters l in the sections z of S_i (u0: a start)."""
    jet = lambda ll, uu: geometry.surface_jet(member, flank, ll, uu)  # noqa: E731
    u = _solve_u(jet, np.asarray(l, dtype=float), z, u0)
    return geometry.surface(member, flank, l, u).point, u


def fillet_in_section(geometry, member, flank, z, psi, u0=0.0):
    """(points (..., 3), u) of the root fillet at parameters psi in the sections z of S_i."""
    jet = lambda pp, uu: fillet_kernels.fillet_jet(geometry, member, flank, pp, uu)  # noqa: E731
    u = _solve_u(jet, np.asarray(psi, dtype=float), z, u0)
    return fillet_kernels.fillet(geometry, member, flank, psi, u).point, u


def flank_at_radius(geometry, member, flank, z, radius, l0=None, strict=True):
    """(point, l, u) of the flank at a radius in the section z (solver.section's Newton), elementwise
    over z and radius (floats l, u for scalar input).  Where Newton does not converge: NoSolution, or
    with ``strict=False`` NaN there."""
    m = geometry.member(member)
    start = m.cutter_addendum_mm / np.cos(geometry.normal_pressure_angle) if l0 is None else l0
    sp = point_at_radius(m.tooth_surface, flank, geometry.surface_params(member), radius, z, start)
    if not strict:
        bad = ~np.asarray(sp.converged)
        return (np.where(bad[..., None], np.nan, sp.point), np.where(bad, np.nan, sp.l_mm), np.where(bad, np.nan, sp.u_mm))
    if not sp.converged.all():
        raise NoSolution(f"no {member} {flank} flank point at radius {radius} mm in the section z = {z} mm")
    return (sp.point, float(sp.l_mm), float(sp.u_mm)) if sp.l_mm.ndim == 0 else (sp.point, sp.l_mm, sp.u_mm)


def undercut_top(geometry, member, flank, z, psi0, l0, uf0=0.0, us0=0.0):
    """(point, psi, l) where the fillet crosses the flank in the section z (the top of an undercut):
    fillet(psi, u_f) = flank(l, u_s) with both in the section, by Newton from (psi0, l0, uf0, us0)."""
    psi, l, uf, us = float(psi0), float(l0), float(uf0), float(us0)
    for _ in range(_MAX_ITER):
        jf = fillet_kernels.fillet_jet(geometry, member, flank, psi, uf)
        js = geometry.surface_jet(member, flank, l, us)
        f = np.concatenate([jf.point - js.point, [jf.point[2] - z]])
        jac = np.zeros((4, 4))
        jac[:3, 0], jac[:3, 1] = jf.point_D_pu[:, 0], jf.point_D_pu[:, 1]
        jac[:3, 2], jac[:3, 3] = -js.point_D_lu[:, 0], -js.point_D_lu[:, 1]
        jac[3, 0], jac[3, 1] = jf.point_D_pu[2, 0], jf.point_D_pu[2, 1]
        psi, uf, l, us = np.array([psi, uf, l, us]) - np.linalg.solve(jac, f)
        if np.max(np.abs(f)) < _TOL:
            return js.point, float(psi), float(l)
    raise NoSolution(f"the {member} {flank} fillet does not cross the flank in the section z = {z} mm")


def _crossing(a, b):
    """(i, j) of the first segments of polylines a (n, 2) and b (m, 2) that cross, or None (all pairs at once)."""
    p, r = a[:-1, None, :], (a[1:] - a[:-1])[:, None, :]  # (n-1, 1, 2)
    q, s = b[None, :-1, :], (b[1:] - b[:-1])[None, :, :]  # (1, m-1, 2)
    den = r[..., 0] * s[..., 1] - r[..., 1] * s[..., 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = ((q[..., 0] - p[..., 0]) * s[..., 1] - (q[..., 1] - p[..., 1]) * s[..., 0]) / den
        v = ((q[..., 0] - p[..., 0]) * r[..., 1] - (q[..., 1] - p[..., 1]) * r[..., 0]) / den
    hit = (t >= 0) & (t <= 1) & (v >= 0) & (v <= 1)
    rows = np.nonzero(hit.any(axis=1))[0]
    if not rows.size:
        return None
    i = int(rows[0])
    return i, int(np.nonzero(hit[i])[0][0])


class FormLimit(NamedTuple):
    l_mm: float  # the flank's rack parameter there
    radius_mm: float
    psi: float  # the fillet's parameter there (the junction psi_J without undercut)


def form_limit(geometry, member, flank, z, samples=400) -> FormLimit | None:
    """(l, radius, psi) where the flank's usable involute starts in the section z of S_i, or None where
    it has none (the tip circle inside the base circle: the section is all fillet and undercut).

    Without undercut it is the junction with the fillet (l = l_t of the tip round).  Where the
    section is undercut the fillet cuts the flank: the form limit is the top of the undercut,
    the crossing of fillet and flank in the section (found on sampled curves, then by Newton).
    """
    from . import sections

    tr = fillet_kernels.tip_round(geometry, member)
    l_t, psi_j = float(tr.junction_l), float(tr.junction_psi)
    s = sections.section(geometry, member, sections.face_z(geometry, member, z))
    if float(getattr(s, f"undercut_depth_{flank}")) <= 0:
        return FormLimit(l_t, float(getattr(s, f"form_radius_{flank}")), psi_j)
    if not float(s.tip_radius) > float(getattr(s, f"base_radius_{flank}")):
        return None  # no involute up to the tip: nothing above an undercut
    try:
        _, l_tip, _ = flank_at_radius(geometry, member, flank, z, float(s.tip_radius))
        t = np.linspace(0.0, 1.0, samples)
        ls = l_t + (l_tip - l_t) * t ** 3  # dense near the junction: a mild undercut is a small loop there
        psis = psi_j * (1 - (1 - t) ** 3)
        fl, ul = flank_in_section(geometry, member, flank, z, ls)
        fi, ui = fillet_in_section(geometry, member, flank, z, psis)
        # the top of the undercut: the crossing farthest up the flank
        hit = _crossing(fl[::-1, :2], fi[:, :2])
        if hit is None:
            return _body_form_limit(geometry, member, flank, z, samples)
        i, j = hit
        k = len(ls) - 1 - i
        point, psi, l = undercut_top(geometry, member, flank, z, psis[j], ls[k], ui[j], ul[k])
    except NoSolution:  # a section Newton found no point: the flank does not reach up there
        return _body_form_limit(geometry, member, flank, z, samples)
    return FormLimit(l, float(np.hypot(point[0], point[1])), psi)


def _body_form_limit(geometry, member, flank, z, samples) -> FormLimit | None:
    """The form limit of the member's body (``tooth.body``: the unmodified rack's flank and fillet) where
    a modified flank does not cross its fillet in an undercut section: the root fillet does not carry a
    tip or end relief, a lead slope or a user model, and a relief of micrometres can move the flank off
    the fillet's loop there.  The body's crossing is then the top of the undercut (the modified flank
    runs into the fillet from it, ``ToothSampler.flank_points``); None for the body itself."""
    from .body import body_pair, is_body

    if is_body(geometry, member):
        return None
    return form_limit(body_pair(geometry, member), member, flank, z, samples)

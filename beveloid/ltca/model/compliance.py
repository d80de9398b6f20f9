"""The compliance of a beveloid tooth pair: how a cell's pressure moves every cell of its pair.

``BeveloidCompliance`` is the operator the contact solver (:mod:`.lcp`) sees for one mesh
position: per tooth pair, the Boussinesq/Love half-space matrix of that pair's grid (both bodies,
through E*) plus the thin-slice bending/shear/root compliance of both members' teeth, each tooth
taken as the **equivalent spur tooth** of its normal section (normal module and pressure angle,
z_v = z / cos^3 beta, the reference section's profile shift; the conical change of the shift along
the face and the helix are not in the beam: docs/loaded_contact.md).  The tooth deflection is
evaluated on the grid's centre line (the cells on its along-axis) and applied to every cell of the
same along index: C_tooth[(i,a),(j,b)] = T[a, b] area_(j,b), T = g_pinion K_pinion + g_gear K_gear.
Only the active columns are ever formed (the solver needs C[S, S] and C[:, S] p_S).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..mechanics import halfspace, lcp, tooth_compliance
from .grid import edges


@dataclass(frozen=True)
class MemberTooth:
    """The equivalent spur tooth of one member, with its slice compliance tabulated on radii."""

    section: tooth_compliance.ToothSection
    pitch_radius_mm: float  # of the member (generating pitch cylinder)
    virtual_pitch_radius_mm: float
    face_width_mm: float
    toe_mm: float
    direction: float
    plate_height_mm: float  # tooth height: the face coupling's plate (tooth_compliance.face_coupling_per_mm)
    poisson: float
    table_radius_mm: np.ndarray  # equivalent-tooth radii of the tabulated slice compliance
    table_mm2_per_n: np.ndarray  # g on table_radius_mm x table_radius_mm

    def line_compliance(self, points) -> np.ndarray:
        """:func:`tooth_line_compliance` (the interface the FE tooth shares: beveloid.fe.tooth.FeTooth)."""
        return tooth_line_compliance(self, points)

    def line_compliances(self, points) -> np.ndarray:
        """(Q, n, n) :func:`tooth_line_compliance` of Q point sets (Q, n, 3) at once."""
        return tooth_line_compliances(self, points)


def member_tooth(geom, which, e_mpa, nu) -> MemberTooth:
    m = geom.member(which)
    mn, an = geom.normal_module_mm, geom.normal_pressure_angle
    zv = int(min(400, max(6, round(m.teeth / math.cos(m.helix_angle) ** 3))))
    x = float(np.clip(m.rack_shift_mm / mn, -1.0, 1.0))
    ha, hf = m.tip_height_mm / mn, m.cutter_addendum_mm / mn
    section = tooth_compliance.involute_tooth_section(mn, zv, an, x, ha, hf)
    toe, heel = m.face_limits
    rb = 0.5 * mn * zv * math.cos(an)
    radii = np.linspace(max(rb * (1 + 1e-9), section.radius_mm[0] * (1 + 1e-6)), section.radius_mm[-1], 96)
    load = tooth_compliance.involute_load_points(mn, zv, radii, an, x)
    load = tooth_compliance.LoadPoints(np.clip(load.centreline_radius_mm, section.radius_mm[0] * (1 + 1e-9),
                                               section.radius_mm[-1]), load.load_angle_rad)
    table = tooth_compliance.slice_compliance_mm2_per_n(section, load, e_mpa, nu)
    return MemberTooth(section=section, pitch_radius_mm=m.pitch_radius_mm, virtual_pitch_radius_mm=0.5 * mn * zv,
                       face_width_mm=m.face_width_mm, toe_mm=toe, direction=1.0 if heel > toe else -1.0,
                       plate_height_mm=(ha + hf) * mn, poisson=nu,
                       table_radius_mm=radii, table_mm2_per_n=table)


def tooth_line_compliance(tooth: MemberTooth, points) -> np.ndarray:
    """T[a, b] (mm/N): deflection along the normal at point a per unit normal force at point b.

    Points (n, 3) in the member's frame.  The radius maps onto the equivalent spur tooth by its
    height above the pitch cylinder; the axial position onto the face for the coupling.
    """
    return tooth_line_compliances(tooth, np.asarray(points, dtype=float)[None])[0]


def tooth_line_compliances(tooth: MemberTooth, points) -> np.ndarray:
    """(Q, n, n) :func:`tooth_line_compliance` of Q point sets (Q, n, 3) in one pass (the face coupling of
    every line in one product: :func:`beveloid.ltca.mechanics.tooth_compliance.face_couplings_per_mm`)."""
    points = np.asarray(points, dtype=float)
    r = np.hypot(points[..., 0], points[..., 1])
    rad = tooth.table_radius_mm
    rv = np.clip(tooth.virtual_pitch_radius_mm + (r - tooth.pitch_radius_mm), rad[0], rad[-1])
    rv = np.where(np.isfinite(rv), rv, rad[0])  # cells off the surfaces: never loaded, any finite value
    pos = np.interp(rv, rad, np.arange(rad.size))  # bilinear in the table (96 radii over the flank)
    i0 = np.minimum(pos.astype(int), rad.size - 2)
    f = pos - i0
    t = tooth.table_mm2_per_n
    a, b = i0[..., :, None], i0[..., None, :]
    fa, fb = f[..., :, None], f[..., None, :]
    g = ((1 - fa) * (1 - fb) * t[a, b] + fa * (1 - fb) * t[a + 1, b] + (1 - fa) * fb * t[a, b + 1]
         + fa * fb * t[a + 1, b + 1])
    w = tooth.face_width_mm
    hz = 1e-3 * w
    z = np.clip(np.nan_to_num((points[..., 2] - tooth.toe_mm) * tooth.direction, nan=0.5 * w), hz, w - hz)
    if tooth.plate_height_mm == 0.0:
        k = np.zeros(g.shape)
        k[..., np.arange(z.shape[-1]), np.arange(z.shape[-1])] = 1.0 / (2.0 * hz)
    else:
        k = tooth_compliance.face_couplings_per_mm(z, hz, w, tooth.plate_height_mm, tooth.poisson)
    return g * k


def pair_tooth_compliance(tooth_p, tooth_g, pinion_points, gear_points) -> np.ndarray:
    """(ny, ny) tooth compliance (mm/N) of both members along one grid's centre line; symmetrised
    (Maxwell reciprocity: the beam model is symmetric up to the coupling's cell averaging).  A tooth
    is any object with ``line_compliance(points)``: :class:`MemberTooth` (plate) or the FE tooth.
    A centre-line point off the surfaces (NaN: the line leaves the flank there, while cells of the
    same along index across the line may still touch) bends as its nearest point on the surfaces
    (:func:`on_surface_line`)."""
    return pair_tooth_compliances(tooth_p, tooth_g, np.asarray(pinion_points, float)[None],
                                  np.asarray(gear_points, float)[None])[0]


def pair_tooth_compliances(tooth_p, tooth_g, pinion_points, gear_points) -> np.ndarray:
    """(Q, ny, ny) :func:`pair_tooth_compliance` of Q lines (points (Q, ny, 3)) at once: a tooth with
    ``line_compliances(points)`` (the FE tooth) takes them all in one product."""
    t = sum(_line_compliances(tooth, on_surface_lines(pts)) for tooth, pts in ((tooth_p, pinion_points),
                                                                                (tooth_g, gear_points)))
    return 0.5 * (t + np.swapaxes(t, -1, -2))


def _line_compliances(tooth, points):
    many = getattr(tooth, "line_compliances", None)
    return many(points) if many is not None else np.stack([tooth.line_compliance(q) for q in points])


def on_surface_lines(points) -> np.ndarray:
    """:func:`on_surface_line` of each line (Q, n, 3); only the lines with a point off the surfaces change."""
    p = np.array(points, dtype=float)
    ok = np.all(np.isfinite(p), axis=-1)
    for q in np.flatnonzero(~ok.all(axis=-1) & ok.any(axis=-1)):
        p[q] = on_surface_line(p[q])
    return p


def on_surface_line(points) -> np.ndarray:
    """Points (n, 3) along a line with each non-finite point replaced by the nearest finite one along
    the line (linear between two, the end one beyond them); unchanged when none is finite (a pair
    without contact: never loaded)."""
    p = np.asarray(points, dtype=float)
    ok = np.all(np.isfinite(p), axis=1)
    if ok.all() or not ok.any():
        return p
    i = np.arange(p.shape[0])
    return np.stack([np.interp(i, i[ok], p[ok, c]) for c in range(3)], axis=1)


def halfspace_matrix(across_half_mm, along_half_mm, nx, ny, e_star_mpa):
    """The Love matrix (mm/MPa) of a uniform nx x ny grid of the given half-extents."""
    return halfspace.tensor_influence_matrix_mm_per_mpa(edges(across_half_mm, nx), edges(along_half_mm, ny),
                                                        e_star_mpa)


class BeveloidCompliance(lcp.Compliance):
    """C of every tooth pair at one position: that pair's half-space matrix ``halfspace[k]`` plus
    its tooth compliance ``tooth[k][line_a, line_b] area_b`` (``line``: a cell's along index;
    ``area[k]``: pair k's cell area), cells pair-major, as dense symmetric blocks (the LTCA itself
    makes their rows from compact tables as its solve reads them: :func:`beveloid.ltca.passes.cycle.block_rows`)."""

    def __init__(self, halfspace_blocks, tooth, line, area):
        n = line.size
        blocks = tuple(np.asarray(c, dtype=float) + np.asarray(t, dtype=float)[np.ix_(line, line)] * float(a)
                       for c, t, a in zip(halfspace_blocks, tooth, area))
        object.__setattr__(self, "blocks", blocks)
        object.__setattr__(self, "slices", tuple(slice(k * n, (k + 1) * n) for k in range(len(blocks))))
        object.__setattr__(self, "symmetric", (True,) * len(blocks))

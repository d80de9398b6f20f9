"""Cells that cover a member's bounded flank patch: the data of the patch-clearance pre-check
(derivations/patch_clearance.py; beveloid/solver/core.py ``patches_apart``) that proves a
tooth pair's patches cannot touch.

The patch is the part of the flank R(l, u) whose four margins (flank_boundaries) are >= 0.  It
lies in a parameter box [0, l_max] x [u_min, u_max], found here from the margins themselves
(grown until no cell that may hold a patch point touches the box's far edges, then shrunk to
the cells that may).  The box is cut into CELLS root cells.  A cell (or any part of it) with
parameter half-diagonal h and centre c lies inside the sphere about R(c) of radius

    rho = h * stretch + patch_tol,    stretch = max |R_lu|_2 + h max |R_llu|_F,

the maxima over SAMPLES x SAMPLES nodes of the cell (|R_lu|_2: the largest singular value of
the first derivatives, the map's largest stretch; |R_llu|_F: the second derivatives, R_lu
counted twice, a bound on how much the stretch grows between nodes: every point of the cell is
within h/2 of a node (h/4 for the root cells), and the h term allows at least twice the sampled
bend over that distance).  Every
point of the cell is within h of c in (l, u), so its image is within rho of R(c).  The core
splits a cell whose sphere it cannot place outside the gear blank into four, each with the
root's ``stretch``, down to a set depth.  A root cell whose sphere lies outside the member's own
blank (some margin g_i(R(c)) + rho |grad g_i| < 0) holds no patch point and is left out.

Cached per (geometry, member, flank); a few milliseconds with the generated numpy kernels.
"""
from __future__ import annotations

import functools
import math
from typing import NamedTuple

import numpy as np

from ..errors import UserError
from ..generated import flank_boundaries, tca_kernels

#: root cells along l and u of the patch's parameter box
CELLS = (4, 16)
#: nodes per root cell and direction at which the stretch and bend are sampled
SAMPLES = 5


class UnboundedPatch(UserError, RuntimeError):
    """A flank patch that no parameter box holds (a tooth so undercut or pointed that its flank does not
    close between the form limit, the tip cone and the face ends): the contact solver cannot bound it.
    A RuntimeError for the whole-tooth and explore callers, which record it as no contact; a UserError
    (one line, exit 2) for a command that needs the contact."""


class PatchCover(NamedTuple):
    """Root cells covering a flank patch (member frame S_i, mm): one row per cell, the fields
    named by CELL_FIELDS."""

    cells: np.ndarray  # (n, len(CELL_FIELDS))
    box: tuple  # (l_min, l_max, u_min, u_max) of the parameter box, mm


#: the columns of PatchCover.cells
CELL_FIELDS = ("x_mm", "y_mm", "z_mm", "l_mm", "u_mm", "half_l_mm", "half_u_mm", "stretch")

#: the most cells along u of the box search (a face width of 1000 mm on a small module)
MAX_BOX_CELLS = 2000


def _nodes(geom, which, flank, l, u):
    """Point, |R_lu|_2 and |R_llu|_F at the node grid (l, u)."""
    m = geom.member(which)
    params = geom.surface_params(which)
    jet = tca_kernels.surface_jet(m.tooth_surface, flank, l, u, params)
    d2 = tca_kernels.surface_second_derivatives(m.tooth_surface, flank, l, u, params).point_D2_lu
    rl, ru = jet.point_D_lu[..., 0], jet.point_D_lu[..., 1]
    gll, guu, glu = (rl * rl).sum(-1), (ru * ru).sum(-1), (rl * ru).sum(-1)  # R_lu^T R_lu: its larger eigenvalue
    mean, dev = (gll + guu) / 2, np.hypot((gll - guu) / 2, glu)
    stretch = np.sqrt(mean + dev)  # |R_lu|_2, the largest singular value
    bend = np.sqrt((d2[..., 0] ** 2).sum(-1) + 2 * (d2[..., 1] ** 2).sum(-1) + (d2[..., 2] ** 2).sum(-1))
    return jet.point, stretch, bend


def _outside_own_blank(geom, which, centre, radius):
    """True where the sphere lies outside the member's blank (so its cell holds no patch point)."""
    mar = flank_boundaries.flank_margins(centre, 0.0, geom.member(which).blank())
    slope = np.sqrt((mar.margins_D_point ** 2).sum(-1))
    out = np.zeros(centre.shape[:-1], dtype=bool)
    for k, name in enumerate(flank_boundaries.BOUNDARIES):
        if name != "form limit":  # l >= 0 holds in the whole box
            out |= mar.margins[..., k] + radius * slope[..., k] < 0
    return out


def _cell_max(a, k):
    """Max of a node grid a ((k nl + 1) x (k nu + 1)) over each cell's (k + 1) x (k + 1) nodes."""
    nl, nu = (a.shape[0] - 1) // k, (a.shape[1] - 1) // k
    rows = np.maximum(a[:-1].reshape(nl, k, -1).max(axis=1), a[k::k])  # (nl, k nu + 1)
    return np.maximum(rows[:, :-1].reshape(nl, nu, k).max(axis=2), rows[:, k::k])


def _grid(geom, which, flank, box, cells, patch_tol, samples=SAMPLES):
    """Centres (nl, nu, 3), radii (nl, nu) and stretch bounds (nl, nu) of the cells of ``box``
    cut (nl, nu) times, sampled on samples x samples nodes per cell (odd: one is the centre)."""
    nl, nu = cells
    k = samples - 1
    L, U = np.meshgrid(np.linspace(box[0], box[1], k * nl + 1), np.linspace(box[2], box[3], k * nu + 1),
                       indexing="ij")
    point, stretch, bend = _nodes(geom, which, flank, L, U)
    h = 0.5 * math.hypot((box[1] - box[0]) / nl, (box[3] - box[2]) / nu)
    bound = _cell_max(stretch, k) + h * _cell_max(bend, k)
    return point[k // 2::k, k // 2::k], h * bound + patch_tol, bound


def _box(geom, which, flank, patch_tol):
    """A parameter box holding the whole patch: grown until no cell that may hold a patch point
    touches its far edges, then shrunk to the cells that may.  A face far longer than the tooth
    is deep (cells far larger than the depth, so that every edge cell "may hold a patch point")
    is searched again with cells about as long as wide."""
    box = _box_search(geom, which, flank, patch_tol, square=False)
    if box is None:
        box = _box_search(geom, which, flank, patch_tol, square=True)
    if box is None:
        raise UnboundedPatch(f"the {which}'s {flank} flank patch is unbounded in its parameters: the flank does not close"
                             " between its form limit, tip cone and face ends, so the contact cannot be solved"
                             " (`beveloid design` reports the whole tooth: undercut, pointed)")
    return box


def _box_search(geom, which, flank, patch_tol, square):
    m = geom.member(which)
    depth = m.cutter_addendum_mm + m.tip_height_mm + abs(m.rack_shift_mm)
    l_max = 1.5 * depth / math.cos(geom.normal_pressure_angle)
    half = (m.face_width_mm / 2 + abs(m.reference_section_offset_mm) + l_max) / (
        math.cos(m.helix_angle) * math.cos(m.cone_angle))
    u0, u1 = -1.2 * half, 1.2 * half
    cells = (3 * CELLS[0], 3 * CELLS[1])
    for _ in range(8):
        box = (0.0, l_max, u0, u1)
        if square:
            cells = (cells[0], max(3 * CELLS[1], min(MAX_BOX_CELLS, math.ceil(cells[0] * (u1 - u0) / l_max))))
        centre, radius, _ = _grid(geom, which, flank, box, cells, patch_tol, samples=3)
        keep = ~_outside_own_blank(geom, which, centre, radius)
        if not keep.any():
            raise RuntimeError(f"the {which}'s {flank} flank patch is empty (no point inside its blank)")
        il, iu = np.nonzero(keep)
        grow_l, grow_u = il.max() >= cells[0] - 1, iu.min() == 0 or iu.max() >= cells[1] - 1
        if not (grow_l or grow_u):
            dl, du = (box[1] - box[0]) / cells[0], (box[3] - box[2]) / cells[1]
            return (0.0, (il.max() + 1) * dl, u0 + iu.min() * du, u0 + (iu.max() + 1) * du)
        if grow_l or not square:
            l_max = 2 * l_max
        if grow_u or not square:
            u0, u1 = u0 - (u1 - u0) / 2, u1 + (u1 - u0) / 2
    return None


@functools.lru_cache(maxsize=64)
def patch_cover(geom, which, flank, patch_tol_mm=1e-9) -> PatchCover:
    """The root cells covering ``which`` member's ``flank`` patch (see the module docstring)."""
    box = _box(geom, which, flank, patch_tol_mm)
    nl, nu = CELLS
    centre, radius, stretch = _grid(geom, which, flank, box, CELLS, patch_tol_mm)
    hl, hu = (box[1] - box[0]) / (2 * nl), (box[3] - box[2]) / (2 * nu)
    L, U = np.meshgrid(box[0] + hl * (2 * np.arange(nl) + 1), box[2] + hu * (2 * np.arange(nu) + 1), indexing="ij")
    columns = dict(x_mm=centre[..., 0], y_mm=centre[..., 1], z_mm=centre[..., 2], l_mm=L, u_mm=U,
                   half_l_mm=np.full_like(L, hl), half_u_mm=np.full_like(L, hu), stretch=stretch)
    cells = np.stack([columns[f] for f in CELL_FIELDS], axis=-1)
    keep = ~_outside_own_blank(geom, which, centre, radius)
    return PatchCover(np.ascontiguousarray(cells[keep]), box)

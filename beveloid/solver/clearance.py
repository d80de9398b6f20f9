"""The proof that two bounded patches cannot touch (patches_apart over the pinion patch cover,
beveloid/solver/patch_cover.py; derivations/patch_clearance.py).

Plain Python in numba's subset: compiled with the rest of the core by
:mod:`beveloid.solver.backends` (see :mod:`beveloid.solver.core`)."""
import math
import typing

import numpy as np

from ..generated.tca_kernels import BOUNDARIES
from ..generated.tca_kernels_scalar import (
    N_BOUNDARIES, blank_margins_point, pinion_in_gear_frame_point, surface_jet_point,
)
from .patch_cover import CELL_FIELDS

#: How often patches_apart may halve a cell of the pinion patch cover (root spheres of a few mm
#: become 1/64 of that) before it gives up the proof.
MAX_SPLITS = 6
#: the form limit is a margin in the rack parameter (l >= 0), not in the point: no sphere test
FORM_LIMIT = BOUNDARIES.index("form limit")
CELL_X, CELL_L, CELL_U = CELL_FIELDS.index("x_mm"), CELL_FIELDS.index("l_mm"), CELL_FIELDS.index("u_mm")
CELL_HALF_L, CELL_HALF_U = CELL_FIELDS.index("half_l_mm"), CELL_FIELDS.index("half_u_mm")
CELL_STRETCH = CELL_FIELDS.index("stretch")


class ClearanceScratch(typing.NamedTuple):
    """Work arrays of patches_apart (one thread)."""

    rotation: np.ndarray  # (3, 3) L_21
    translation: np.ndarray  # (3,) T_21
    margins: np.ndarray  # (N_BOUNDARIES,)
    margins_D_point: np.ndarray  # (N_BOUNDARIES, 3)
    margins_D_l: np.ndarray  # (N_BOUNDARIES,)
    point_in_gear: np.ndarray  # (3,) a pinion point in S_2
    point: np.ndarray  # (3,) pinion point in S_1
    normal: np.ndarray  # (3,)
    point_D_lu: np.ndarray  # (3, 2)
    normal_D_lu: np.ndarray  # (3, 2)
    stack: np.ndarray  # (4 MAX_SPLITS + 4, 5) cells to test: l, u, half_l, half_u, depth


def clearance_scratch():
    """A :class:`ClearanceScratch` (allocate once per thread)."""
    return ClearanceScratch(rotation=np.empty((3, 3)), translation=np.empty(3), margins=np.empty(N_BOUNDARIES),
                            margins_D_point=np.empty((N_BOUNDARIES, 3)), margins_D_l=np.empty(N_BOUNDARIES),
                            point_in_gear=np.empty(3), point=np.empty(3), normal=np.empty(3),
                            point_D_lu=np.empty((3, 2)), normal_D_lu=np.empty((3, 2)),
                            stack=np.empty((4 * MAX_SPLITS + 4, 5)))


def sphere_outside_blank(p, radius, l, blank, m, mdp, mdl):
    """(the sphere about p lies outside the blank, p itself lies inside it): the sphere is outside
    when some point margin g_i has g_i(p) + radius |grad g_i| < 0 (derivations/patch_clearance.py);
    the form limit (l >= 0) is checked at p only."""
    blank_margins_point(p, l, blank, m, mdp, mdl)
    inside = True
    for b in range(N_BOUNDARIES):
        if m[b] < 0.0:
            inside = False
        if b != FORM_LIMIT and m[b] + radius * math.sqrt(mdp[b, 0] ** 2 + mdp[b, 1] ** 2 + mdp[b, 2] ** 2) < 0.0:
            return True, False
    return False, inside


def patches_apart(problem, cells, phi1, e, patch_tol, cs):
    """True when the pinion's bounded flank cannot meet the gear's at phi1 for any gear angle
    (derivations/patch_clearance.py): every cell of the pinion patch cover (beveloid/solver/patch_cover.py)
    has its sphere outside the pinion blank (no patch point) or, carried into S_2 at phi'_2 = 0,
    outside the gear blank.  A cell that is neither is cut in four, at most MAX_SPLITS times.
    False when that cannot be shown: a cell centre on the patch and inside the gear blank, or a
    cell still undecided after MAX_SPLITS."""
    pinion_blank, gear_blank = problem.pinion_blank, problem.gear_blank
    rot, trans, m, mdp, mdl = cs.rotation, cs.translation, cs.margins, cs.margins_D_point, cs.margins_D_l
    q, pt, nm, dp, dn, stack = cs.point_in_gear, cs.point, cs.normal, cs.point_D_lu, cs.normal_D_lu, cs.stack
    pinion_in_gear_frame_point(phi1, e, problem.pair, rot, trans)
    for i in range(cells.shape[0]):
        stretch = cells[i, CELL_STRETCH]
        stack[0, 0] = cells[i, CELL_L]
        stack[0, 1] = cells[i, CELL_U]
        stack[0, 2] = cells[i, CELL_HALF_L]
        stack[0, 3] = cells[i, CELL_HALF_U]
        stack[0, 4] = 0.0
        top = 1
        while top > 0:
            top -= 1
            l, u, hl, hu, depth = stack[top, 0], stack[top, 1], stack[top, 2], stack[top, 3], stack[top, 4]
            if depth == 0.0:
                for a in range(3):
                    pt[a] = cells[i, CELL_X + a]
            else:
                surface_jet_point(problem.pinion_model, problem.flank, l, u, problem.pinion_params, pt, nm, dp, dn)
            radius = math.sqrt(hl * hl + hu * hu) * stretch + patch_tol
            out, on_patch = sphere_outside_blank(pt, radius, l, pinion_blank, m, mdp, mdl)
            if out:
                continue
            for a in range(3):
                q[a] = trans[a] + rot[a, 0] * pt[0] + rot[a, 1] * pt[1] + rot[a, 2] * pt[2]
            out, in_gear = sphere_outside_blank(q, radius, 0.0, gear_blank, m, mdp, mdl)
            if out:
                continue
            if (on_patch and in_gear) or depth >= MAX_SPLITS:
                return False
            for a in range(2):
                for b in range(2):
                    stack[top, 0] = l + (a - 0.5) * hl
                    stack[top, 1] = u + (b - 0.5) * hu
                    stack[top, 2] = 0.5 * hl
                    stack[top, 3] = 0.5 * hu
                    stack[top, 4] = depth + 1.0
                    top += 1
    return True

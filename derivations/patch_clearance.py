"""Whether a pinion flank patch can touch the gear's flank patch at all, whatever the gear angle
(the pre-check of edge contact; not in the paper; see beveloid/patch_cover.py and
beveloid/solver/core.py).

A tooth pair at pinion angle phi'_1 touches where a pinion flank point and a gear flank point
coincide for some gear angle phi'_2 (edge_contact.py).  The gear turns about its own axis z_2:
by Eq 34, M_f2(phi'_2) = M_f2(0) R_z(phi'_2), so a point fixed in S_f is seen in S_2 at

    M_2f(phi'_2) R_f = R_z(-phi'_2) M_21 R_1,    M_21 = M_f2(0)^-1 M_f1(phi'_1)

(:func:`invariance_residual` is zero).  The gear blank's point margins (tip, toe, heel of
flank_boundaries.margins) depend on a point of S_2 only through sqrt(x^2 + y^2) and z, which
R_z leaves unchanged.  Every point of the gear's bounded flank has those margins >= 0, at any
phi'_2; so a pinion flank point can coincide with one of them only if M_21 R_1 lies inside the
gear blank.  When no point of the pinion's bounded flank does, the two patches cannot touch at
phi'_1 for any phi'_2: the pair is OUTSIDE, proven.

The runtime covers the pinion patch by spheres (beveloid/patch_cover.py) and checks each centre
c with radius rho: a sphere lies outside the blank when some margin g_i has g_i(M_21 c) +
rho |grad g_i| < 0, because each margin changes by at most |grad g_i| per mm and M_21 is rigid.
|grad g_i| is the same at every point (:func:`margin_slopes`: 1/cos(gamma) for the tip cone,
1 for the toe and heel planes), so the generated margins_D_point at the centre gives it.
"""
import sympy as sp

from . import eq28_38_meshing_model as mm
from . import flank_boundaries as fb
from .common import rot_z
from .symbols import gamma, phi2p


def rigid_inverse(M):
    """Inverse of a 4x4 rigid transform [L t; 0 1]: [L^T, -L^T t; 0 1]."""
    L, t = M[:3, :3], M[:3, 3]
    return L.T.row_join(-L.T * t).col_join(sp.Matrix([[0, 0, 0, 1]]))


#: S_1 -> S_2 at phi'_2 = 0
M_21 = rigid_inverse(mm.M_f2.subs(phi2p, 0)) * mm.M_f1
L_21 = M_21[:3, :3]
T_21 = M_21[:3, 3]


def invariance_residual():
    """M_2f(phi'_2) M_f1 - R_z(-phi'_2) M_21 (4x4; zero: the gear angle only turns S_2 about z_2)."""
    return rigid_inverse(mm.M_f2) * mm.M_f1 - rot_z(-phi2p) * M_21


def margin_slopes():
    """|grad g_i| of the tip, toe and heel margins over a point of S_i: (1/cos gamma, 1, 1) at
    every point (the Lipschitz constants of the clearance test)."""
    m = fb.margins()
    rows = [m[i, :].jacobian(list(fb.POINT)) for i in (1, 2, 3)]
    return [sp.sqrt(sp.simplify(sum(v ** 2 for v in r))) for r in rows]


def expected_slopes():
    return [1 / sp.Abs(sp.cos(gamma)), sp.Integer(1), sp.Integer(1)]

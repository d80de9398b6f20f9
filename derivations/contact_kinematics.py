"""Beyond the print: the surface velocities at a contact point of the assembled pair, for the
tribology (beveloid/tribology/: sliding, entrainment, friction power, flash temperature).

A point of the pinion flank, R_1 in S_1, is at R_f = M_f1(phi'_1) R_1 in the fixed frame (Eq 30).
The pinion turns at d phi'_1/dt = omega_1, so that material point moves at

    V_1 = dM_f1/dphi'_1 [R_1; 1] omega_1.

The gear material point at the same place R_f is R_2 = M_f2(phi'_2)^-1 R_f (Eq 32); it moves at

    V_2 = dM_f2/dphi'_2 M_f2^-1 [R_f; 1] dphi'_2/dt,    dphi'_2/dt = -(N_1/N_2) omega_1

(the mean ratio of the rigid mesh: the TE of beveloid.mesh is phi'_2 + (N_1/N_2) phi'_1 up to a
constant, so the transmission error's rate is left out).  Because M_f2(phi'_2) = M_f2(0) R_z(phi'_2)
(patch_clearance.invariance_residual), dM_f2/dphi'_2 M_f2^-1 = M_f2(0) (R_z' R_z^-1) M_f2(0)^-1 does
not depend on phi'_2: it is taken at phi'_2 = 0.  Both are rigid-body velocity fields omega x (R - c)
about each member's axis; :func:`velocity_field_residual` checks that they are, symbolically.

With the contact normal n_f = L_f1 n_1 (the pinion's outward normal), each velocity's part in the
common tangent plane is V_t = V - (V.n) n.  The tribology needs

    sliding velocity  V_s = V_1t - V_2t   (of the pinion surface relative to the gear's)
    sum velocity      V_sum = V_1t + V_2t (twice the entraining velocity)

and (V_1 - V_2).n, the approach speed along the normal, which is zero at a point of rigid conjugate
contact (a check of the point, not an input).  Lengths are in mm and angular speeds in rad/s: the
velocities are divided by 1000 to give m/s.
"""
import sympy as sp

from . import eq28_38_meshing_model as mm
from .symbols import N1, N2, phi1p, phi2p

#: the pinion's angular speed (rad/s) and the contact point and normal in S_1
omega1 = sp.Symbol("omega_1", real=True)
POINT = sp.Matrix(sp.symbols("p1_0:3", real=True))
NORMAL = sp.Matrix(sp.symbols("n1_0:3", real=True))
MM_PER_M = 1000


def _velocity_of_point_on_gear(r_f):
    """dM_f2/dphi'_2 M_f2^-1 [r_f; 1] at phi'_2 = 0 (mm per rad of gear rotation)."""
    m0 = mm.M_f2.subs(phi2p, 0)
    d0 = mm.M_f2.diff(phi2p).subs(phi2p, 0)
    l0, t0 = m0[:3, :3], m0[:3, 3]
    inv = l0.T.row_join(-l0.T * t0).col_join(sp.Matrix([[0, 0, 0, 1]]))
    return (d0 * inv * r_f.col_join(sp.Matrix([1])))[:3, 0]


def velocities(point=POINT, normal=NORMAL):
    """{name: expression} of the contact kinematics (see the module docstring), in m/s."""
    r_f = mm.L_f1 * point + mm.M_f1[:3, 3]
    n_f = mm.L_f1 * normal
    v1 = (mm.M_f1.diff(phi1p) * point.col_join(sp.Matrix([1])))[:3, 0] * omega1 / MM_PER_M
    v2 = _velocity_of_point_on_gear(r_f) * (-N1 / N2) * omega1 / MM_PER_M
    tangent = lambda v: v - v.dot(n_f) * n_f  # noqa: E731
    v1t, v2t = tangent(v1), tangent(v2)
    return {"point": r_f, "normal": n_f, "pinion_velocity": v1t, "gear_velocity": v2t,
            "sliding_velocity": v1t - v2t, "sum_velocity": v1t + v2t, "approach_speed": (v1 - v2).dot(n_f)}


def velocity_field_residual():
    """Both velocity fields minus omega x (R - c) about each member's axis (zero vectors): the pinion
    turns about z_f through M_f1's origin, the gear about L_f2 e_z through M_f2's origin."""
    r_f = sp.Matrix(sp.symbols("r_0:3", real=True))
    ez = sp.Matrix([0, 0, 1])
    v1 = (mm.M_f1.diff(phi1p) * mm.M_f1.inv() * r_f.col_join(sp.Matrix([1])))[:3, 0]
    w1 = ez.cross(r_f - mm.M_f1[:3, 3])
    axis2 = mm.L_f2[:, 2].subs(phi2p, 0)
    w2 = axis2.cross(r_f - mm.M_f2[:3, 3])
    return sp.simplify(v1 - w1), sp.simplify(_velocity_of_point_on_gear(r_f) - w2)

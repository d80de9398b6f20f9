"""Eqs 28-38: the assembled pair with the five assembly errors, and the TCA system.

Transforms are products of elementary ones (Eq 30, 33, 34):

    M_f1 = T(0, 0, d_w1 - b_c1) R_z(phi'_1)
    M_fq = T(E, 0, 0) R_x(-delta) T(0, 0, d_w2 - b_c2)
    M_q2 = T(dx_q, dy_q, dz_q) R_x(-dgamma_h) R_y(dgamma_v) R_z(phi'_2)

Tooth surfaces are those of Eqs 4-7 with outward normals, so in contact n_f1 = -n_f2.
Because both L_fi are rotations (L^T L = I, checked), |n_fi| = 1 and one
component of n_f1 + n_f2 = 0 is dependent: Eq 38 keeps the three position components and
the x_f and z_f components of the normal sum (the y_f component is the large one near the
pitch point, so dropping it keeps the system best conditioned).
"""
import sympy as sp

from . import paper
from .common import Equation, rot_x, rot_y, rot_z, trans, uniform, uniform_deg
from .symbols import E, b_c1, b_c2, d_w1, d_w2, delta, dg_h, dg_v, dx_q, dy_q, dz_q, phi1p, phi2p

M_f1 = trans(0, 0, d_w1 - b_c1) * rot_z(phi1p)
M_fq = trans(E, 0, 0) * rot_x(-delta) * trans(0, 0, d_w2 - b_c2)
M_q2 = trans(dx_q, dy_q, dz_q) * rot_x(-dg_h) * rot_y(dg_v) * rot_z(phi2p)
M_f2 = M_fq * M_q2
L_f1 = M_f1[:3, :3]
L_f2 = M_f2[:3, :3]

UNKNOWNS_DOC = "(l1, u1, l2, u2, phi'_2)"
ERRORS = (dx_q, dy_q, dz_q, dg_v, dg_h)


def tca_residual(p1, n1, p2, n2):
    """Eq 38 from surfaces in S1/S2 (3-vectors, unit outward normals): five scalar equations."""
    rf1 = L_f1 * p1 + M_f1[:3, 3]
    rf2 = L_f2 * p2 + M_f2[:3, 3]
    nsum = L_f1 * n1 + L_f2 * n2
    return sp.Matrix([rf1[0] - rf2[0], rf1[1] - rf2[1], rf1[2] - rf2[2], nsum[0], nsum[2]])


def _sampler(rng):
    return {phi1p: uniform(rng, -3, 3), phi2p: uniform(rng, -3, 3), d_w1: uniform(rng, -300, 300),
            d_w2: uniform(rng, -300, 300), b_c1: uniform(rng, -20, 20), b_c2: uniform(rng, -20, 20),
            E: uniform(rng, 20, 500), delta: uniform_deg(rng, 3, 45), dx_q: uniform(rng, -1, 1),
            dy_q: uniform(rng, -1, 1), dz_q: uniform(rng, -1, 1), dg_v: uniform_deg(rng, -1, 1),
            dg_h: uniform_deg(rng, -1, 1)}


def equations():
    return [
        Equation(28, "position transform R_fi = M_fi R_i", "definition", used_by="eq28_38_meshing_model.tca_residual"),
        Equation(29, "normal transform n_fi = L_fi n_i", "definition", used_by="eq28_38_meshing_model.tca_residual"),
        Equation(30, "pinion placement M_f1", "derived", printed=paper.eq30, derived=M_f1, sampler=_sampler, symbolic=True,
                 steps=[r"$M_{f1} = T(0,0,d_{w1}-b_{c1})\,R_z(\varphi'_1)$"]),
        Equation(31, "pinion rotation L_f1", "derived", printed=paper.eq31, derived=L_f1, sampler=_sampler, symbolic=True,
                 steps=[r"Upper-left $3\times3$ of $M_{f1}$."]),
        Equation(32, "gear placement M_f2 = M_fq M_q2", "derived", printed=paper.eq32, derived=M_f2, sampler=_sampler,
                 symbolic=True, steps=[r"Product of Eqs 33 and 34."]),
        Equation(33, "frame of the aligned gear M_fq", "derived", printed=paper.eq33, derived=M_fq, sampler=_sampler,
                 symbolic=True, steps=[r"$M_{fq} = T(E,0,0)\,R_x(-\delta)\,T(0,0,d_{w2}-b_{c2})$"]),
        Equation(34, "gear with assembly errors M_q2", "derived", printed=paper.eq34, derived=M_q2, sampler=_sampler,
                 symbolic=True,
                 steps=[r"$M_{q2} = T(\Delta x_q,\Delta y_q,\Delta z_q)\,R_x(-\Delta\gamma_h)\,R_y(\Delta\gamma_v)\,"
                        r"R_z(\varphi'_2)$: $\Delta\gamma_v$ turns the gear axis in the $x_f z$ plane, $\Delta\gamma_h$ "
                        r"then about $x_f$."],
                 note="Row 3 of the printed M_q2 reads (-sin dgv cos dgh, -sin dgh, cos dgh cos dgv): R_x(-dgh) R_y(dgv)."),
        Equation(35, "gear rotation L_f2", "derived", printed=paper.eq35, derived=L_f2, sampler=_sampler, symbolic=True,
                 steps=[r"Rotation parts of $M_{fq}$ and $M_{q2}$."]),
        Equation(36, "contact: common point", "definition", used_by="eq28_38_meshing_model.tca_residual"),
        Equation(37, "contact: common normal", "definition", used_by="eq28_38_meshing_model.tca_residual",
                 note="With outward normals on both surfaces the contact condition is n_f1 = -n_f2."),
        Equation(38, "five independent equations", "derived",
                 printed=[sp.eye(3), sp.eye(3)], derived=[L_f1.T * L_f1, L_f2.T * L_f2], sampler=_sampler,
                 steps=[r"$L_{f1}^T L_{f1} = I$ and $L_{f2}^T L_{f2} = I$ (the check below), so "
                        r"$|n_{f1}| = |n_{f2}| = 1$ and one normal component is dependent.",
                        r"$f = [R_{f1}-R_{f2}]_{x,y,z} \cup [n_{f1}+n_{f2}]_{x,z} = 0$, unknowns "
                        r"$(l_1,u_1,l_2,u_2,\varphi'_2)$ for a given $\varphi'_1$."],
                 note="Normal components kept: x_f and z_f of n_f1 + n_f2 (the y_f one is dependent up to sign)."),
    ]

"""Eqs 8-17: working pitch cones, their tangency at the pitch point P, helix matching, offset.

Frames (Sf of Eq 33): the pinion axis is z_f; the gear axis passes through (E, 0, 0) with
direction (0, sin delta, cos delta); x_f is the common perpendicular.  Cone i has its apex
a distance d_i *behind* the foot of the common perpendicular on its axis and opens toward
+z_i:

    pinion:  R_f1 = (0, 0, -d1) + R'_1(theta1, u1)
    gear:    R_f2 = T(E, 0, 0) R_x(-delta) T(0, 0, -d2) R'_2(theta2, u2)

Both normals are the outward normals of Eq 9.  Two cones touching from outside have
*opposite* outward normals, so the tangency the model solves is R_f1 = R_f2 and
n_f1 = -n_f2 (the paper prints n_f1 = n_f2, Eq 11: a sign convention it does not state).
"""
import functools

import sympy as sp

from . import paper
from .common import Equation, hom, rot_x, trans, uniform, uniform_deg
from .symbols import (
    E, beta_w1, beta_w2, d1, d2, delta, eta, gamma_w, gamma_w1, gamma_w2, r_w1, r_w2, theta, theta1, theta2,
    u_c,
)

sin, cos, sqrt = sp.sin, sp.cos, sp.sqrt


def cone_point(th, uu, gw):
    """Eq 8: pitch cone with apex at the origin, generatrix length uu."""
    return sp.Matrix([uu * sin(gw) * cos(th), uu * sin(gw) * sin(th), uu * cos(gw)])


def cone_normal(th, gw):
    """Eq 9 derived: (dR/dtheta x dR/du) / |.|, outward."""
    rr = cone_point(th, u_c, gw)
    n = rr.diff(th).cross(rr.diff(u_c))
    return (n / (u_c * sin(gw))).applyfunc(sp.simplify)  # tiny expression: one factor to cancel


M_f2_cone = trans(E, 0, 0) * rot_x(-delta) * trans(0, 0, -d2)


def placed_cones():
    """Points and outward normals of both cones in Sf, as functions of (theta_i, u_i)."""
    u1, u2 = sp.symbols("u1 u2", positive=True)
    p1 = cone_point(theta1, u1, gamma_w1) + sp.Matrix([0, 0, -d1])
    n1 = paper.eq09.subs({theta: theta1, gamma_w: gamma_w1})
    p2 = (M_f2_cone * hom(cone_point(theta2, u2, gamma_w2)))[:3, 0]
    n2 = rot_x(-delta)[:3, :3] * paper.eq09.subs({theta: theta2, gamma_w: gamma_w2})
    return (u1, u2), p1, n1, p2, n2


def solve_tangency():
    """Solve Eqs 10-11 for the pitch point: returns dict of derived closed forms (a new dict each
    call, over one solve per process: the checks of Eqs 10-18 and the design chain all use it)."""
    return dict(_solve_tangency())


@functools.cache
def _solve_tangency():
    (u1, u2), p1, n1, p2, n2 = placed_cones()
    c1, s1, c2, s2 = sp.symbols("c1 s1 c2 s2", real=True)  # cos/sin theta_i as unknowns
    trig = {cos(theta1): c1, sin(theta1): s1, cos(theta2): c2, sin(theta2): s2}
    normal_eqs = list((n1 + n2).subs(trig))
    lin = sp.solve(normal_eqs, [s1, s2, c1], dict=True)[0]
    # branch: P lies between the axes, so the gear's cone point faces -x: cos(theta2) < 0
    c2_val = -sqrt(1 - lin[s2] ** 2)
    sol = {s2: lin[s2], c2: c2_val}
    sol[s1] = lin[s1].subs(sol)
    sol[c1] = lin[c1].subs(sol)
    # positions: r_wi = u_i sin(gamma_wi)
    pos_eqs = [e.subs(trig).subs(sol) for e in (p1 - p2)]
    pos_eqs = [e.subs({u1: r_w1 / sin(gamma_w1), u2: r_w2 / sin(gamma_w2)}) for e in pos_eqs]
    (rw1_sol,) = sp.solve(pos_eqs[0], r_w1)
    dd = sp.solve([pos_eqs[1], pos_eqs[2]], [d1, d2], dict=True)[0]
    return {
        "cos_theta1": sol[c1], "sin_theta1": sol[s1], "cos_theta2": sol[c2], "sin_theta2": sol[s2],
        "r_w1": rw1_sol, "d1": dd[d1], "d2": dd[d2], "normal_eqs": normal_eqs,
    }


def generatrices_and_normal(sol):
    """Unit generatrices tau_1, tau_2 and the pinion's outward normal at P, in Sf."""
    c1, s1, c2, s2 = sol["cos_theta1"], sol["sin_theta1"], sol["cos_theta2"], sol["sin_theta2"]
    g1 = sp.Matrix([sin(gamma_w1) * c1, sin(gamma_w1) * s1, cos(gamma_w1)])
    g2 = rot_x(-delta)[:3, :3] * sp.Matrix([sin(gamma_w2) * c2, sin(gamma_w2) * s2, cos(gamma_w2)])
    n1 = sp.Matrix([c1 * cos(gamma_w1), s1 * cos(gamma_w1), -sin(gamma_w1)])
    return g1, g2, n1


def _cos_eta_in_theta():
    """tau_1 . tau_2 written with theta_1, theta_2 kept symbolic (for the derivation text)."""
    th = {"cos_theta1": cos(theta1), "sin_theta1": sin(theta1), "cos_theta2": cos(theta2), "sin_theta2": sin(theta2)}
    g1, g2, _ = generatrices_and_normal(th)
    return sp.expand(g1.dot(g2))


def helix_matching():
    """Tooth directions t_i = cos(b_i) g_i + sin(b_i) (g_i x n_i) (RH positive, n_i outward) coincide.

    In the common tangent plane take e = g1, f = g1 x n1 and write g2 = cos(eta) e + sin(eta) f,
    n2 = -n1.  Returns (t1, t2) in the (e, f) basis and the solution for eta.
    """
    e = sp.Matrix([1, 0, 0])
    n = sp.Matrix([0, 0, -1])  # so that f = e x n = (0, 1, 0)
    f = e.cross(n)
    g2 = cos(eta) * e + sin(eta) * f
    t1 = cos(beta_w1) * e + sin(beta_w1) * e.cross(n)
    t2 = cos(beta_w2) * g2 + sin(beta_w2) * g2.cross(-n)
    t2 = t2.applyfunc(lambda x: sp.simplify(sp.trigsimp(x)))
    return t1, t2


def sampler(rng):
    while True:
        d = {delta: uniform_deg(rng, 3, 45), gamma_w1: uniform_deg(rng, 0.2, 8), gamma_w2: uniform_deg(rng, 0.2, 8),
             E: uniform(rng, 20, 500), r_w2: uniform(rng, 10, 300), r_w1: uniform(rng, 10, 300),
             beta_w1: uniform_deg(rng, -45, 45)}
        s2 = (sp.sin(d[delta]) ** 2 - sp.sin(d[gamma_w1]) ** 2 - sp.sin(d[gamma_w2]) ** 2
              - 2 * sp.sin(d[gamma_w1]) * sp.sin(d[gamma_w2]) * sp.cos(d[delta]))
        if s2 > 0.05 * sp.sin(d[delta]) ** 2:
            return d


def equations():
    sol = solve_tangency()
    g1, g2, n1 = generatrices_and_normal(sol)
    t1, t2 = helix_matching()
    cos_eta = g1.dot(g2)
    sin_eta = g2.dot(g1.cross(n1))
    S = paper.S
    e_from_12 = sp.solve(sp.Eq(r_w1, paper.eq12), E)[0]
    eqs = [
        Equation(8, "pitch cone", "definition", used_by="eq08_17_pitch_cones.cone_point"),
        Equation(9, "pitch cone unit normal", "derived", printed=paper.eq09,
                 derived=cone_normal(theta, gamma_w), symbolic=True,
                 sampler=lambda rng: {theta: uniform_deg(rng, -180, 180), gamma_w: uniform_deg(rng, 0.2, 8)},
                 steps=[r"$n' = \frac{\partial R'/\partial\theta \times \partial R'/\partial u}{u\sin\gamma_w} = %s$"
                        % sp.latex(cone_normal(theta, gamma_w))]),
        Equation(10, "tangency: common point", "definition", used_by="eq08_17_pitch_cones.solve_tangency"),
        Equation(11, "tangency: common normal", "definition", used_by="eq08_17_pitch_cones.solve_tangency",
                 note="With both normals outward (Eq 9) external tangency needs n_f1 = -n_f2; the print's "
                      "n_f1 = n_f2 holds only with one normal turned inward."),
        Equation(12, "working pitch radius r_w1", "derived", printed=paper.eq12, derived=sol["r_w1"], sampler=sampler,
                 steps=[
                     r"Normals, $n_{f1} + n_{f2} = 0$: $\sin\theta_2 = %s$, $\sin\theta_1 = %s$"
                     % (sp.latex(sol["sin_theta2"]), sp.latex(sol["sin_theta1"])),
                     r"Branch $\cos\theta_2 < 0$ (P between the axes): $\cos\theta_2 = %s$, $\cos\theta_1 = %s$"
                     % (sp.latex(sol["cos_theta2"]), sp.latex(sol["cos_theta1"])),
                     r"x-component of $R_{f1} = R_{f2}$ with $r_{wi} = u_i\sin\gamma_{wi}$: $r_{w1} = %s$"
                     % sp.latex(sol["r_w1"]),
                 ]),
        Equation(13, "pinion mounting distance d1", "derived", printed=paper.eq13, derived=sol["d1"].subs(r_w1, sol["r_w1"]),
                 sampler=sampler,
                 steps=[r"y- and z-components of $R_{f1} = R_{f2}$, linear in $d_1, d_2$: $d_1 = %s$; "
                        r"compared with $r_{w1}$ from Eq 12" % sp.latex(sol["d1"])]),
        Equation(14, "gear mounting distance d2", "derived", printed=paper.eq14.subs(r_w1, paper.eq12),
                 derived=sol["d2"].subs(r_w1, sol["r_w1"]), sampler=sampler,
                 steps=[r"$d_2 = %s$; both sides compared with $r_{w1}$ from Eq 12" % sp.latex(sol["d2"])]),
        Equation(15, "angle between generatrices", "definition", used_by="eq08_17_pitch_cones (Eq 16)",
                 note="The tau_i are the unit generatrices of the pitch cones at P."),
        Equation(16, "helix matching", "derived", printed=paper.eq16_rhs, derived=cos_eta, sampler=sampler,
                 steps=[
                     r"Tooth directions $t_i = \cos\beta_{wi}\,\tau_i + \sin\beta_{wi}\,(\tau_i\times n_i)$ "
                     r"(right hand positive, $n_i$ outward, $n_2 = -n_1$). With $\tau_2 = \cos\eta\,e + \sin\eta\,f$, "
                     r"$e = \tau_1$, $f = \tau_1\times n_1$: $t_1 = %s$, $t_2 = %s$" % (sp.latex(t1.T), sp.latex(t2.T)),
                     r"$t_1 = t_2 \Rightarrow \eta = \beta_{w1} + \beta_{w2}$ (the '+' reading, signed helix angles).",
                     r"From the tangency solution (sines and cosines of $\theta_i$ from Eq 12's steps): "
                     r"$\cos\eta = \tau_1\cdot\tau_2 = %s$" % sp.latex(_cos_eta_in_theta()),
                 ],
                 extra_checks=[("sin(eta) = tau_2.(tau_1 x n_1) = S/(cos gw1 cos gw2) > 0",
                                lambda: sin_eta - S / (cos(gamma_w1) * cos(gamma_w2)))],
                 note="Only the '+' reading with signed helix angles follows; 'cos(eta) = tau1.tau2' means the "
                      "generatrices, not the tooth traces."),
        Equation(17, "offset from the pitch cones", "derived",
                 printed=paper.eq17.subs(beta_w2, sp.acos(paper.eq16_rhs) - beta_w1),
                 derived=e_from_12.subs(S, sp.Symbol("S_")).subs(sp.Symbol("S_"), S), sampler=sampler,
                 steps=[r"Eq 12 solved for $E$: $E = %s$" % sp.latex(e_from_12),
                        r"and $1 - \cos^2\eta = S^2/(\cos^2\gamma_{w1}\cos^2\gamma_{w2})$ from Eq 16, so "
                        r"$S/(\cos\gamma_{w1}\cos\gamma_{w2}) = \sin(\beta_{w1}+\beta_{w2})$."]),
    ]
    return eqs

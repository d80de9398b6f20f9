"""The design procedures of Section 3.4 composed from the derived Eqs 12-27 (for code generation).

Direct design (the reading of equations.md that reproduces Table 1): given
m_n, alpha_n, N1, N2, delta, E, gamma1, gamma2, beta1, x_t1 and a trial alpha_nw,

    xi_n                 Eq 23 (normal base pitch)
    gamma_w1, gamma_w2   Eq 25 (N_z half-sum invariant)
    beta_w1              Eq 26 (N_z half-difference invariant)
    beta_w2 = eta - beta_w1, cos(eta) = tau_1 . tau_2     Eq 16
    beta2                Eq 26 inverted for the gear
    xi_ti, r_i, r_wi     Eq 23, r = N m_n / (2 cos beta)
    E(alpha_nw)          Eq 17 (= Eq 12 solved for E)

and alpha_nw is the root of E(alpha_nw) - E.  Everything else (d_i, pitch point, FPD angles,
transverse pressure angles, x_t2 of Eq 27) follows.  All expressions come from the models,
not from paper.py.

Indirect design: given the working data alpha_nw, gamma_w1, gamma_w2, beta_w1 (and m_n,
alpha_n, N1, N2, delta, x_t1) the same relations run backwards: gamma_i from Eq 25, beta_i
from Eq 26, beta_w2 from Eq 16, E from Eq 17.
"""
import sympy as sp

from . import eq08_17_pitch_cones as cones
from . import eq18_21_line_contact as line
from . import eq22_27_working_data as work
from .eq01_03_rack_cutter import LEFT, RIGHT
from .symbols import (
    E, N1, N2, alpha_n, alpha_nw, beta, beta1, beta_w1, beta_w2, delta, gamma, gamma1, gamma2, gamma_w1, gamma_w2, m_n, r_w1,
    r_w2, x_t1,
)

sin, cos, tan, asin, acos, atan = sp.sin, sp.cos, sp.tan, sp.asin, sp.acos, sp.atan

def tangency():
    """The pitch point's closed forms (Eqs 10-11; solved once per process by the pitch-cone model)."""
    return cones.solve_tangency()


def cos_eta():
    g1, g2, _ = cones.generatrices_and_normal(tangency())
    return g1.dot(g2)


def eta():
    """eta = beta_w1 + beta_w2 (Eq 16) from y = tau_2.(tau_1 x n_1) = sin(eta), x = tau_1.tau_2.

    Both come from the tangency model (Eq 16's check proves the sine positive).  The half-angle
    form 2 atan(y / (1 + x)) (x^2 + y^2 = 1: tau_2 is a unit vector in the plane of tau_1 and
    tau_1 x n_1) keeps full precision where eta -> 0 (small offsets), which arccos of Eq 16
    would lose, and stays complex-analytic (complex-step derivatives).
    """
    g1, g2, n1 = cones.generatrices_and_normal(tangency())
    y, x = g2.dot(g1.cross(n1)), g1.dot(g2)
    return 2 * sp.atan(y / (1 + x))


def _tan_P(sigma, al, be, ga):
    return work.tan_transverse_pressure_angle(sigma).subs({alpha_n: al, beta: be, gamma: ga}, simultaneous=True)


def pair_quantities(gw1, gw2, bw1, bw2, b1, b2, g1_, g2_, alw, xt2_solve=True):
    """Everything downstream of the working angles, as a dict of expressions."""
    xin = cos(alw) / cos(alpha_n)
    r1 = N1 * m_n / (2 * cos(b1))
    r2 = N2 * m_n / (2 * cos(b2))
    xt1_ = xin * cos(bw1) / cos(b1)
    xt2_ = xin * cos(bw2) / cos(b2)
    rw1 = r1 / xt1_
    rw2 = r2 / xt2_
    sol = tangency()
    sub = {gamma_w1: gw1, gamma_w2: gw2, r_w1: rw1, r_w2: rw2}
    E_model = ((r_w1 * cos(gamma_w2) + r_w2 * cos(gamma_w1)) * sin(beta_w1 + beta_w2) / sin(delta)).subs(
        {beta_w1: bw1, beta_w2: bw2, **sub}, simultaneous=True)
    out = dict(xi_n=xin, gamma_w1=gw1, gamma_w2=gw2, beta_w1=bw1, beta_w2=bw2, beta1=b1, beta2=b2,
               gamma1=g1_, gamma2=g2_, r1=r1, r2=r2, xi_t1=xt1_, xi_t2=xt2_, r_w1=rw1, r_w2=rw2, E=E_model)
    subE = {**sub, E: E_model}
    out["d1"] = sol["d1"].subs(subE, simultaneous=True)
    out["d2"] = sol["d2"].subs(subE, simultaneous=True)
    # working mounting distance: axial position of P's transverse plane from the common perpendicular
    out["d_w1"] = rw1 / tan(gw1) - out["d1"]
    out["d_w2"] = rw2 / tan(gw2) - out["d2"]
    for k in ("cos_theta1", "sin_theta1", "cos_theta2", "sin_theta2"):
        out[k] = sol[k].subs(subE, simultaneous=True)
    for name, sigma in (("L", LEFT), ("R", RIGHT)):
        t1 = line.fpd_angle_tan(sigma, alw, bw1, gw1)
        t2 = line.fpd_angle_tan(sigma, alw, bw2, gw2)
        out[f"xi_{name}1"] = atan(t1)
        out[f"xi_{name}2"] = atan(t2)
        out[f"xi_{name}"] = atan(t1) + atan(t2)
        for i, (bb, gg, bw, gw) in enumerate(((b1, g1_, bw1, gw1), (b2, g2_, bw2, gw2)), start=1):
            tp = _tan_P(sigma, alpha_n, bb, gg)
            out[f"alpha_P{name}{i}"] = atan(tp)
            # the working rack's transverse pressure angle (signed); Eq 22's check proves it
            # equals arccos(xi_t cos(alpha_P)) where that is defined
            out[f"alpha_Pw{name}{i}"] = atan(_tan_P(sigma, alw, bw, gw))
    if xt2_solve:
        inv = lambda a: tan(a) - a  # noqa: E731
        lhs1 = 2 * tan(alpha_n) * x_t1 * cos(g1_) / cos(b1)
        rhs = sum(Ni / 2 * (inv(out[f"alpha_PwL{i}"]) + inv(out[f"alpha_PwR{i}"]) - inv(out[f"alpha_PL{i}"])
                            - inv(out[f"alpha_PR{i}"])) for i, Ni in ((1, N1), (2, N2)))
        out["x_t2"] = (rhs - lhs1) * cos(b2) / (2 * tan(alpha_n) * cos(g2_))
    return out


def direct():
    """Direct design as functions of the trial alpha_nw."""
    xin = cos(alpha_nw) / cos(alpha_n)
    gw1 = asin(sin(gamma1) * sin(alpha_n) / sin(alpha_nw))
    gw2 = asin(sin(gamma2) * sin(alpha_n) / sin(alpha_nw))
    bw1 = asin(sin(beta1) * cos(gamma1) / (xin * cos(gw1)))
    bw2 = eta().subs({gamma_w1: gw1, gamma_w2: gw2}, simultaneous=True) - bw1
    b2 = asin(sin(bw2) * xin * cos(gw2) / cos(gamma2))
    return pair_quantities(gw1, gw2, bw1, bw2, beta1, b2, gamma1, gamma2, alpha_nw)


def indirect():
    """Indirect design from working data (alpha_nw, gamma_w1, gamma_w2, beta_w1)."""
    xin = cos(alpha_nw) / cos(alpha_n)
    g1_ = asin(sin(gamma_w1) * sin(alpha_nw) / sin(alpha_n))
    g2_ = asin(sin(gamma_w2) * sin(alpha_nw) / sin(alpha_n))
    bw2 = eta() - beta_w1
    b1 = asin(sin(beta_w1) * xin * cos(gamma_w1) / cos(g1_))
    b2 = asin(sin(bw2) * xin * cos(gamma_w2) / cos(g2_))
    return pair_quantities(gamma_w1, gamma_w2, beta_w1, bw2, b1, b2, g1_, g2_, alpha_nw)

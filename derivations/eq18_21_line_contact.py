"""Eqs 18-21: contact lines of each gear with the common rack and the FPD angle.

A gear and its generating rack touch along a line of the rack flank: the points whose
flank normal meets the instantaneous axis (parallel to the gear axis).  Its direction is
the projection of the gear axis onto the flank plane, k = a - (a.N) N.  The FPD angle of
gear i is the signed angle from the tooth trace T to k_i, positive counter-clockwise about
the flank's outward normal N, for the common rack with working data
(alpha_nw, beta_wi, gamma_wi) -> Eqs 19 (left) and 20 (right).

Eq 18: gear 2 sees the same flank plane of the common rack with the opposite outward
normal, so its signed angle flips and the crossing angle of k_1 and k_2 is xi_1 + xi_2.
The model checks that in Sf itself: the common rack is built at the pitch point P of
Eqs 10-14, both axes are projected onto its flank, and the angle between the projections
is compared with xi_1 + xi_2.
"""
import functools

import sympy as sp

from . import paper
from .common import Equation, rot_y, rot_x, uniform_deg
from .eq08_17_pitch_cones import generatrices_and_normal, solve_tangency
from .eq08_17_pitch_cones import sampler as cone_sampler
from .symbols import alpha_nw, beta_w, beta_w1, delta, gamma_w, gamma_w1, gamma_w2

sin, cos = sp.sin, sp.cos


@functools.lru_cache(maxsize=2)
def _fpd_angle_tan_symbolic(sigma):
    rot = rot_y(gamma_w)[:3, :3] * rot_x(-beta_w)[:3, :3]
    n = rot * sp.Matrix([sin(alpha_nw), -sigma * cos(alpha_nw), 0])  # outward flank normal
    t = rot * sp.Matrix([0, 0, 1])  # tooth trace
    a = sp.Matrix([0, 0, 1])  # gear axis
    k = a - a.dot(n) * n
    # a small rational expression in sines and cosines of three symbols: a targeted trigsimp
    # is quick here (it is never applied to the composed design expressions)
    return sp.trigsimp(sp.cancel(sp.expand(t.cross(k).dot(n)) / sp.expand(t.dot(k))))


def fpd_angle_tan(sigma, al, be, ga):
    """tan of the signed angle from tooth trace to contact line, one gear and its rack."""
    return _fpd_angle_tan_symbolic(sigma).subs({alpha_nw: al, beta_w: be, gamma_w: ga}, simultaneous=True)


def common_rack_crossing(sigma):
    """Signed angle (as sin, cos) from k_2 to k_1 on flank sigma of the common rack, built in Sf."""
    sol = solve_tangency()
    g1, g2, n1 = generatrices_and_normal(sol)
    t = cos(beta_w1) * g1 + sin(beta_w1) * g1.cross(n1)
    Y = t.cross(n1)
    N = sin(alpha_nw) * n1 - sigma * cos(alpha_nw) * Y  # gear 1's outward flank normal
    a1 = sp.Matrix([0, 0, 1])
    a2 = sp.Matrix([0, sin(delta), cos(delta)])
    k1 = a1 - a1.dot(N) * N
    k2 = a2 - a2.dot(N) * N
    return k2.cross(k1).dot(N), k2.dot(k1)


def sampler(rng):
    d = cone_sampler(rng)
    d[alpha_nw] = uniform_deg(rng, 14, 30)
    d[beta_w] = d[beta_w1]
    d[gamma_w] = d[gamma_w1]
    return d


def equations():
    derived_L = fpd_angle_tan(+1, alpha_nw, beta_w, gamma_w)
    derived_R = fpd_angle_tan(-1, alpha_nw, beta_w, gamma_w)
    beta_w2_of_1 = sp.acos(paper.eq16_rhs) - beta_w1  # Eq 16, '+' reading

    def fpd_sum(printed_tan):
        """Eq 18 as printed: xi_1 + xi_2, each from Eq 19/20 with its own working data."""
        return (sp.atan(printed_tan.subs({beta_w: beta_w1, gamma_w: gamma_w1}))
                + sp.atan(printed_tan.subs({beta_w: beta_w2_of_1, gamma_w: gamma_w2})))

    def crossing_angle(sigma):
        """Signed angle from k_2 to k_1 on the common rack's flank, measured in Sf."""
        sn, cs = common_rack_crossing(sigma)
        return sp.atan2(sn, cs)

    return [
        Equation(18, "FPD angle of the pair", "derived", sampler=sampler,
                 printed=[fpd_sum(paper.eq19_tan), fpd_sum(paper.eq20_tan)],
                 derived=[crossing_angle(+1), crossing_angle(-1)],
                 steps=[r"Common rack at P: trace $t = \cos\beta_{w1}\tau_1 + \sin\beta_{w1}(\tau_1\times n_1)$, "
                        r"flank normal $N = \sin\alpha_{nw} n_1 \mp \cos\alpha_{nw}(t\times n_1)$.",
                        r"$k_i = a_i - (a_i\cdot N)N$; the signed angle from $k_2$ to $k_1$ about $N$ equals "
                        r"$\xi_1 + \xi_2$ with each $\xi_i$ from Eqs 19-20 and $\beta_{w2}$ from Eq 16."],
                 note="Left flank of the pinion meshes with the left flank of the gear (same plane of the common rack)."),
        Equation(19, "FPD angle, left flank", "derived", printed=paper.eq19_tan, derived=derived_L, sampler=sampler,
                 symbolic=True,
                 steps=[r"$\tan\xi_{L} = \frac{(T\times k)\cdot N}{T\cdot k}$, with $k = a - (a\cdot N)N$ the "
                        r"projection of the gear axis $a$ onto the flank (normal $N$, tooth trace $T$), "
                        r"cancelled and trig-simplified: $%s$" % sp.latex(derived_L)]),
        Equation(20, "FPD angle, right flank", "derived", printed=paper.eq20_tan, derived=derived_R, sampler=sampler,
                 symbolic=True,
                 steps=[r"$\tan\xi_{R} = %s$" % sp.latex(derived_R)]),
        Equation(21, "approximate line contact", "definition", used_by="beveloid.design (reported FPD angles)",
                 note="A design target (xi ~ 0), not an equation to derive."),
    ]

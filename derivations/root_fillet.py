"""The root fillet: the envelope of the rack's tip round (issue 22; not in the paper).

The rack's tip round.  In the normal section of Eqs 1-3 (x_n along the rack's depth axis,
positive out of the gear; Y across the teeth; u along the tooth) the straight edge of flank
sigma is  E(l) = (l cos(alpha_n) - a + s, sigma (l sin(alpha_n) - a tan(alpha_n) - b)),  and the
rack's tip line is x_n = -a + s.  The rack material lies on the side the normal
n_e = (sin(alpha_n), -sigma cos(alpha_n)) points to (``rack_normal``), and above the tip line.
A circle of radius rho = rho_a0 inside the rack tooth, tangent to the tip line and to the edge,
has its centre rho above the tip line and rho from the edge along n_e:

    C = E(l_t) + rho n_e,   C_x = -a + s + rho   =>   l_t = rho (1 - sin(alpha_n)) / cos(alpha_n),

so the straight edge now starts at l = l_t (the rack's form point), and the round is

    Q(psi) = C - rho n(psi),   n(psi) = (cos psi, -sigma sin psi),   0 <= psi <= pi/2 - alpha_n,

with psi = 0 on the tip line (the root) and psi = pi/2 - alpha_n at the junction with the edge
(n(pi/2 - alpha_n) = n_e).  n(psi) points into the rack, i.e. out of the generated tooth.

The largest round that fits: the round's tangent point on the tip line, sigma Y_C, must not pass
the centre line of the rack tooth, sigma Y = -pi m_n / 2 (the gear tooth is centred on Y = 0 and
the pitch is pi m_n).  sigma Y_C = l_t sin(alpha_n) - a tan(alpha_n) - b - rho cos(alpha_n)
= -a tan(alpha_n) - b - rho (1 - sin(alpha_n)) / cos(alpha_n), hence

    rho <= rho_max = (pi m_n / 2 - b - a tan(alpha_n)) cos(alpha_n) / (1 - sin(alpha_n)).

At rho_max the two rounds of a rack tooth meet on its centre line (a full round tip).

Crowning (``crowned_flank``) displaces the straight edge by delta(l, u) along -n_e: in a normal
section the edge becomes a parabola whose point at l_t is E(l_t) - delta_J n_e (delta_J = delta(l_t, u))
and whose normal there is n_e' = (n_e + delta_l t_l) / sqrt(1 + delta_l^2), t_l = (cos alpha_n,
sigma sin alpha_n) (delta_l = d delta / dl at l_t, independent of u).  The round moves with the rack
and stays tangent to it at the junction: its centre is  C' = E(l_t) - delta_J n_e + rho n_e',  and
since dn/dpsi = -t_l at psi = pi/2 - alpha_n, n_e' = n(psi_J) with

    psi_J = pi/2 - alpha_n - atan(delta_l),

so the round is  Q(psi) = C' - rho n(psi),  0 <= psi <= psi_J (psi = 0 its deepest point, which cuts
the root).  Without crowning C' = C and psi_J = pi/2 - alpha_n.

In three dimensions (rotated by R_c, u added along e_u) the round's u-derivative is
R_c(e_u - delta_u n_e), and the normal N = R_c(n(psi) + delta_u sin(psi + alpha_n) e_u) is orthogonal
to it (n . n_e = sin(psi + alpha_n)) and to Q_psi = -rho R_c n'(psi), and points out of the tooth.
At psi_J, N is parallel to the crowned edge's normal n_e + delta_l t_l + delta_u e_u
(sin(psi_J + alpha_n) = 1/sqrt(1 + delta_l^2)): point and tangent plane are continuous.

The fillet is the envelope of the family M_ic(phi) Q' (Eqs 4-6) by the same meshing condition
(Eq 7, ``crowned_flank.roll_angle``): phi(psi, u).  For rho = 0 the round is the rack's tip edge
(a line along u); psi then only selects the normal direction among those orthogonal to the
edge, and the envelope condition picks the roll angle at which the swept edge has that normal:
the (psi, u) patch is the trochoidal surface swept by the tip edge, in the same parameters.
"""
import sympy as sp

from . import crowned_flank as cf
from . import eq04_07_tooth_surface as involute
from .interface import Field
from .eq01_03_rack_cutter import rack_rotation
from .symbols import a, alpha_n, b, l, m_n, phi, s, u

rho = sp.Symbol("rho_a0", nonnegative=True)  # the rack's tip round radius (mm)
psi = sp.Symbol("psi", real=True)  # the fillet's profile parameter (rad): 0 at the root, pi/2 - alpha_n at the junction

PARAMETERS = (
    Field("cutter_tip_radius_mm", rho, "mm", "radius rho_a0 of the rack's tip round (0: sharp rack)"),
    Field("normal_module_mm", m_n, "mm", "normal module m_n"),
) + cf.PARAMETERS[:3]


def junction_l():
    """l_t: where the straight edge meets the round (the rack's form point)."""
    return rho * (1 - sp.sin(alpha_n)) / sp.cos(alpha_n)


def junction_psi():
    """psi_J: where the round meets the (crowned) straight edge."""
    return sp.pi / 2 - alpha_n - sp.atan(cf.crowning().diff(l).xreplace({l: junction_l()}))


def max_radius():
    """The largest round that fits the rack tooth (a full round tip)."""
    return (sp.pi * m_n / 2 - b - a * sp.tan(alpha_n)) * sp.cos(alpha_n) / (1 - sp.sin(alpha_n))


def edge_normal(sigma):
    """n_e in the normal section (x_n, Y, u)."""
    return sp.Matrix([sp.sin(alpha_n), -sigma * sp.cos(alpha_n), 0])


def round_normal_section(sigma, delta=0):
    """(centre, point Q(psi), n(psi)) of the round in the normal section (x_n, Y, u), u = 0, with the
    rack's crowning delta at the junction (the round's centre C' above)."""
    lt = junction_l()
    ca, sa = sp.cos(alpha_n), sp.sin(alpha_n)
    edge = sp.Matrix([lt * ca - a + s, sigma * (lt * sa - a * sp.tan(alpha_n) - b), 0])
    pj = junction_psi()
    n_j = sp.Matrix([sp.cos(pj), -sigma * sp.sin(pj), 0])
    centre = edge - delta * edge_normal(sigma) + rho * n_j
    n = sp.Matrix([sp.cos(psi), -sigma * sp.sin(psi), 0])
    return centre, centre - rho * n, n


def junction_crowning():
    """delta(l_t, u) and its u-derivative: the rack's crowning at the junction."""
    d = cf.crowning().xreplace({l: junction_l()})
    return d, d.diff(u)


def round_point(sigma, delta=None):
    """Q'(psi, u) in the cutter frame S_c: the round, translated with the crowned rack."""
    delta = junction_crowning()[0] if delta is None else delta
    _, q, _ = round_normal_section(sigma, delta)
    return rack_rotation() * (q + sp.Matrix([0, 0, u]))


def round_normal(sigma, delta_u=None, unit=True):
    """The normal of Q' (out of the generated tooth); unit=False: before normalising."""
    delta_u = junction_crowning()[1] if delta_u is None else delta_u
    _, _, n = round_normal_section(sigma)
    k = delta_u * sp.sin(psi + alpha_n)
    v = rack_rotation() * (n + sp.Matrix([0, 0, k]))
    return v / sp.sqrt(1 + k ** 2) if unit else v


def fillet_surface(sigma):
    """Explicit fillet of flank sigma in S_i: (point, unit outward normal, phi(psi, u))."""
    pc = round_point(sigma)
    nn = round_normal(sigma, unit=False)
    phi_pu = cf.roll_angle(pc, nn)
    point = involute.generated_family(pc).xreplace({phi: phi_pu})
    normal = (involute.M_ic[:3, :3] * round_normal(sigma)).xreplace({phi: phi_pu})
    return point, normal, phi_pu

"""Flank micro-geometry: tip relief, end relief and lead slope on the generated tooth (issue 20).

Crowning (crowned_flank.py) shapes the rack; these shape the generated tooth.  Take the point q
of the member's tooth surface before these modifications (the crowned surface: the involute one
when both crowning amounts are zero), in the member frame S_i, and its outward unit normal n.
With rho = sqrt(q_x^2 + q_y^2), z = q_z - b_c the axial coordinate from the centre of the face
(the face is centred on the working pitch circle, z = b_c = reference_section_offset_mm in S_i),
rho_a(z) the member's tip-cone radius at q_z (flank_boundaries.tip_radius, the TCA's blank) and
W the face width, the removal along n, into the tooth, is

    delta = C_a max(0, (rho - (rho_a - h_a)) / h_a)^e_a                 tip relief
          + C_e max(0, (|z| - (W/2 - L_e)) / L_e)^e_e                   end relief (toe and heel)
          + f_b z / (W/2)                                               lead slope

(C_a, C_e, f_b input in um, used in mm), and the modified surface is

    P(l, u) = q(l, u) - delta(q(l, u)) n(l, u).

Its unit normal is the normalised P_l x P_u, on the side of n (the sign is fixed per flank
by the base surface's orientation, ``ORIENTATION``); every derivative follows from P by the
chain rule (the envelope of Eq 7 is not redone: P is a displacement of a generated surface).

The ramps.  max(0, t)^e is written as Piecewise((0, t <= 0), (t ((2 - e) + (e - 1) t), True)):
the polynomial t ((2 - e) + (e - 1) t) equals t^e for the two shapes e = 1 (linear) and e = 2
(parabolic), the only exponents the spec lets through, and is a polynomial (no pow of a runtime
exponent in the kernels).  Its derivatives are taken branch by branch, so at the kink t = 0 they
are the one-sided derivatives of the unrelieved side (zero).  The end relief's |z| is split into a
heel ramp (z - z_0) / L_e and a toe ramp (-z - z_0) / L_e, z_0 = W/2 - L_e > 0 (the spec refuses
L_e >= W/2): at most one is positive, so the sum is the definition's term.

``tooth_surface_late`` writes P over abstract functions (the base point and normal, and delta,
each a function of (l, u)); the generator differentiates those small trees and ``substitute``
replaces the derivatives by the base model's own late forms (crowned_flank.tooth_surface_late),
then by their explicit forms.
"""
import sympy as sp

from . import crowned_flank as base
from .common import on_entries, xreplace_all
from .interface import Field
from .flank_boundaries import tip_height, tip_radius
from .symbols import l, u

UM = base.UM
W = base.W

C_a = sp.Symbol("C_a", nonnegative=True)  # tip relief amount (um)
h_tr = sp.Symbol("h_tr", positive=True)  # tip relief height (mm): called h_a in the issue
e_a = sp.Symbol("e_a", positive=True)  # tip relief exponent: 1 linear, 2 parabolic
C_e = sp.Symbol("C_e", nonnegative=True)  # end relief amount (um)
L_e = sp.Symbol("L_e", positive=True)  # end relief length (mm)
e_e = sp.Symbol("e_e", positive=True)  # end relief exponent
f_b = sp.Symbol("f_b", real=True)  # lead slope (um, + removes at z = +W/2)
b_c = sp.Symbol("b_c", real=True)  # face centre in S_i (mm)

#: the shape keys: the TOML gives a name, the kernels take the exponent
SHAPES = {"linear": 1.0, "parabolic": 2.0}
MAX_RELIEF_UM = 200.0

PARAMETERS = base.PARAMETERS + (
    Field("tip_height_mm", tip_height, "mm",
          "tip above the rack pitch plane along the rack depth axis (filled from the design)"),
    Field("reference_section_offset_mm", b_c, "mm", "b_c: the face centre in S_i (filled from the design)"),
    Field("tip_relief_um", C_a, "um", "tip relief C_a: removal at the tip, along the normal"),
    Field("tip_relief_height_mm", h_tr, "mm", "tip relief height h_a: radial height of the relieved band below the tip"),
    Field("tip_relief_shape", e_a, "1", "tip relief shape: \"linear\" (exponent 1) or \"parabolic\" (2)"),
    Field("end_relief_um", C_e, "um", "end relief C_e: removal at each face end (toe and heel)"),
    Field("end_relief_length_mm", L_e, "mm", "end relief length L_e: axial length of each relieved end zone"),
    Field("end_relief_shape", e_e, "1", "end relief shape: \"linear\" (exponent 1) or \"parabolic\" (2)"),
    Field("lead_slope_um", f_b, "um", "lead slope f_b: removal at z = +W/2 from the face centre (negative: at z = -W/2)"),
)
#: generated from the crowned rack and then displaced: the FPD check's straight-edged premise does not hold
STRAIGHT_EDGED_RACK = False
#: numeric input keys: {name: (default, lowest, highest)}.  The heights and lengths default to
#: 1 mm (they only matter with a non-zero amount; the kernels divide by them); the spec also
#: refuses a height not below the working depth and a length not below half the face.
KEYS = {
    **base.KEYS,
    "tip_relief_um": (0.0, 0.0, MAX_RELIEF_UM),
    "tip_relief_height_mm": (1.0, 0.001, 100.0),
    "end_relief_um": (0.0, 0.0, MAX_RELIEF_UM),
    "end_relief_length_mm": (1.0, 0.001, 1000.0),
    "lead_slope_um": (0.0, -MAX_RELIEF_UM, MAX_RELIEF_UM),
}
#: keys given by name in the TOML: {name: (default name, {name: value in the kernels})}
CHOICE_KEYS = {"tip_relief_shape": ("parabolic", SHAPES), "end_relief_shape": ("parabolic", SHAPES)}
SELECTED_BY = ("tip_relief_um", "end_relief_um", "lead_slope_um")


def ramp(t, e):
    """max(0, t)^e for e in {1, 2}, one-sided (zero) derivatives at t = 0."""
    return sp.Piecewise((0, t <= 0), (t * ((2 - e) + (e - 1) * t), True))


def removal(q):
    """delta (mm) at a base surface point q = (x, y, z) in S_i."""
    rho = sp.sqrt(q[0] ** 2 + q[1] ** 2)
    z = q[2] - b_c
    z0 = W / 2 - L_e
    tip = C_a * ramp((rho - (tip_radius(q[2]) - h_tr)) / h_tr, e_a)
    ends = C_e * (ramp((z - z0) / L_e, e_e) + ramp((-z - z0) / L_e, e_e))
    return UM * (tip + ends + f_b * z / (W / 2))


_q = sp.Matrix([sp.Function(f"q_micro_{c}")(l, u) for c in "xyz"])  # base point, abstract
_n = sp.Matrix([sp.Function(f"n_micro_{c}")(l, u) for c in "xyz"])  # base unit normal, abstract
_d = sp.Function("delta_micro")(l, u)  # the removal delta(q(l, u)), abstract


def _orientation(sigma):
    """+1 or -1: the side of P_l x P_u on which the base's outward normal lies (per flank; the
    sign of (q_l x q_u) . n, evaluated on a sample involute tooth and constant over the flank)."""
    from .eq04_07_tooth_surface import tooth_surface
    from .symbols import a, alpha_n, b, beta, gamma, r, s

    p, n, _ = tooth_surface(sigma)
    c = p.diff(l).cross(p.diff(u))
    value = c.dot(n).subs({alpha_n: 0.35, beta: 0.3, gamma: 0.1, a: 3.75, b: 2.36, s: 0.2, r: 40.0,
                           l: 4.0, u: 1.0})
    return 1 if float(value) > 0 else -1


ORIENTATION = {1: None, -1: None}


def orientation(sigma):
    if ORIENTATION[sigma] is None:
        ORIENTATION[sigma] = _orientation(sigma)
    return ORIENTATION[sigma]


def modified_surface(q, n, d, sigma):
    """(point, unit normal) of q - d n, with d a function of (l, u)."""
    p = q - d * n
    c = p.diff(l).cross(p.diff(u))
    return p, orientation(sigma) * c / sp.sqrt(c.dot(c))


_ORDERS = ((), (l,), (u,), (l, l), (l, u), (u, u))
_TAGS = ("", "_l", "_u", "_ll", "_lu", "_uu")


def _abstract_jets():
    """{abstract base value or derivative: its jet symbol}, in stage order."""
    out = {}
    for name, vec in (("q", _q), ("n", _n)):
        for c, f in zip("xyz", vec):
            for v, tag in zip(_ORDERS, _TAGS):
                out[f.diff(*v) if v else f] = sp.Symbol(f"_jet_{name}{c}{tag}", real=True)
    return out


def tooth_surface_staged(sigma):
    """(point, normal, roll angle, substitute, stages): the modified surface over the abstract base
    point, normal and removal; ``substitute`` writes an expression over the jet symbols of the
    base point and normal (to second order) and ``stages`` gives each jet symbol its explicit
    value (the base model's late forms, made explicit once): the kernels compute the base jets,
    then the modification over them."""
    bp, bn, bphi, base_sub = base.tooth_surface_late(sigma)
    point, normal = modified_surface(_q, _n, _d, sigma)
    jets = _abstract_jets()
    forms = {f: form for f, form in list(zip(_q, bp)) + list(zip(_n, bn))}
    keys = list(jets)
    explicit = base_sub(sp.Matrix([forms[k.expr].diff(*k.variables) if isinstance(k, sp.Derivative) else forms[k]
                                   for k in keys]))
    stages = tuple((jets[k], e) for k, e in zip(keys, explicit))
    # delta and its derivatives: stages over the base jets
    explicit_d = removal(_q)
    delta = {}
    for v, tag in zip(_ORDERS, _TAGS):
        sym = sp.Symbol(f"_jet_delta{tag}", real=True)
        delta[_d.diff(*v) if v else _d] = sym
        stages += ((sym, (explicit_d.diff(*v) if v else explicit_d).xreplace(jets)),)
    phi_explicit = base_sub(bphi)

    def substitute_all(out):
        out = xreplace_all(xreplace_all(out, delta), jets)
        return xreplace_all(out, {bphi: phi_explicit}) if isinstance(bphi, sp.Basic) else out

    def substitute(expr):
        return on_entries(expr, substitute_all)

    return point, normal, bphi, substitute, stages


def tooth_surface_late(sigma):
    """The staged surface with the stages substituted (explicit in (l, u); large trees: for checks
    at a few points, not for the generator)."""
    point, normal, ph, substitute, stages = tooth_surface_staged(sigma)

    def explicit(expr):
        out = substitute(expr)
        for sym, e in reversed(stages):  # later stages use earlier ones
            out = out.xreplace({sym: e})
        return out

    return point, normal, ph, explicit


def tooth_surface(sigma):
    """Explicit modified tooth surface of flank sigma in S_i: (point, unit outward normal, phi(l, u))."""
    point, normal, ph, substitute = tooth_surface_late(sigma)
    return substitute(point), substitute(normal), substitute(ph)

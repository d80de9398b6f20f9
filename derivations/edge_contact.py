"""Edge and corner contact: where a flank's boundary curve bears on the mating flank (not in
the paper; see docs/validation.md section 4 and beveloid/solver/core.py).

The contact of a tooth pair at pinion angle phi'_1 is the extreme gear angle phi'_2 over all
pairs of points of the two bounded flank patches that coincide (R_f1 = R_f2).  The coincidence
set is two-dimensional; its extreme is a Karush-Kuhn-Tucker point with an active set A of
boundaries (g_i(l, u) >= 0 are the flank margins of flank_boundaries.py composed with a
member's surface):

    |A| = 0   surface contact: Eq 38 (the tangency);
    |A| = 1   edge contact: R_f1 = R_f2 (3), g_a = 0 (1), and phi'_2 stationary along the curve
              g_a = 0, i.e. the curve's tangent t = R_l g_u - R_u g_l lies in the mating
              flank's tangent plane: (L_fa t) . (L_fb n_b) = 0 (1);
    |A| = 2   corner contact: R_f1 = R_f2 (3), g_a = 0, g_b = 0 (two boundary curves of the two
              members touching, or a corner of one member's patch on the other's flank).

Every system has the unknowns of Eq 38, (l1, u1, l2, u2, phi'_2).  The position rows are those
of Eq 38 (``contact_system``); this module adds, over ABSTRACT surface jets (so every surface
model works unchanged):

* ``boundary_jet``: the four margins of a flank point and their first and second derivatives
  in (l, u), by the chain rule through the surface's point derivatives;
* ``pinion_edge_tangency`` / ``gear_edge_tangency``: the tangency row of a boundary curve of
  one member against the other's flank, with exact derivatives in the unknowns, the errors and
  phi'_1.
"""
import sympy as sp

from . import eq28_38_meshing_model as mm
from . import flank_boundaries as fb
from .symbols import l, phi1p, phi2p


def _vec(prefix, n):
    return sp.Matrix(sp.symbols(f"{prefix}_0:{n}", real=True))


def _mat(prefix, rows, cols):
    return sp.Matrix(rows, cols, sp.symbols(f"{prefix}_0:{rows * cols}", real=True))


def surface_jet_symbols(prefix):
    """Abstract jet of a flank: point (3), [R_l, R_u] (3x2), [R_ll, R_lu, R_uu] (3x3)."""
    return _vec(f"{prefix}_point", 3), _mat(f"{prefix}_point_D_lu", 3, 2), _mat(f"{prefix}_point_D2_lu", 3, 3)


def total_derivative(expr, chain):
    """(d/dl, d/du) of expr through ``chain``: {symbol: (d symbol/dl, d symbol/du)}."""
    return tuple(sum((sp.diff(expr, s) * d[k] for s, d in chain.items()), sp.Integer(0)) for k in range(2))


def _jet_chain(point, point_D_lu, point_D2_lu):
    """How the point and its first derivatives change with (l, u)."""
    chain = {point[i]: (point_D_lu[i, 0], point_D_lu[i, 1]) for i in range(3)}
    for i in range(3):
        chain[point_D_lu[i, 0]] = (point_D2_lu[i, 0], point_D2_lu[i, 1])
        chain[point_D_lu[i, 1]] = (point_D2_lu[i, 1], point_D2_lu[i, 2])
    return chain


def boundary_jet(point, point_D_lu, point_D2_lu):
    """Margins g (4) of the flank point R(l, u), d g / d(l, u) (4x2) and the second derivatives
    [g_ll, g_lu, g_uu] (4x3), composed from flank_boundaries.margins()."""
    m = fb.margins().xreplace(dict(zip(fb.POINT, point)))
    chain = _jet_chain(point, point_D_lu, point_D2_lu)
    chain[l] = (sp.Integer(1), sp.Integer(0))
    first = [total_derivative(m[i], chain) for i in range(m.shape[0])]
    second = []
    for gl, gu in first:
        gll, glu = total_derivative(gl, chain)
        second.append((gll, glu, total_derivative(gu, chain)[1]))
    return m, sp.Matrix(first), sp.Matrix(second)


def curve_tangent(point_D_lu, g_D_lu):
    """Tangent of the boundary curve g(l, u) = 0 on R(l, u): t = R_l g_u - R_u g_l (member frame)."""
    return point_D_lu[:, 0] * g_D_lu[1] - point_D_lu[:, 1] * g_D_lu[0]


def edge_tangency(curve_member):
    """The tangency row (L_fa t) . (L_fb n_b) of a boundary curve on ``curve_member`` ("pinion" or
    "gear") against the other member's flank, and its derivatives.

    Returns (row, d/d unknowns (5), d/d errors (5), d/d phi'_1, symbols) with symbols the
    abstract inputs: (curve point_D_lu, point_D2_lu, g_D_lu, g_D2_lu, mating normal, normal_D_lu).
    """
    other = "gear" if curve_member == "pinion" else "pinion"
    _, dp, d2p = surface_jet_symbols(curve_member)
    g1, g2 = _vec("g_D_lu", 2), _vec("g_D2_lu", 3)
    n, dn = _vec(f"{other}_normal", 3), _mat(f"{other}_normal_D_lu", 3, 2)
    L_curve, L_other = (mm.L_f1, mm.L_f2) if curve_member == "pinion" else (mm.L_f2, mm.L_f1)
    t = curve_tangent(dp, g1)
    row = ((L_curve * t).T * (L_other * n))[0, 0]
    chain = {}
    for i in range(3):
        chain[dp[i, 0]] = (d2p[i, 0], d2p[i, 1])
        chain[dp[i, 1]] = (d2p[i, 1], d2p[i, 2])
    chain[g1[0]] = (g2[0], g2[1])
    chain[g1[1]] = (g2[1], g2[2])
    d_curve = total_derivative(row, chain)
    d_other = tuple(sum((sp.diff(row, n[i]) * dn[i, k] for i in range(3)), sp.Integer(0)) for k in range(2))
    d_lu = (d_curve + d_other) if curve_member == "pinion" else (d_other + d_curve)
    d_unknowns = sp.Matrix(list(d_lu) + [sp.diff(row, phi2p)])
    d_errors = sp.Matrix([sp.diff(row, e) for e in mm.ERRORS])
    return row, d_unknowns, d_errors, sp.diff(row, phi1p), (dp, d2p, g1, g2, n, dn)

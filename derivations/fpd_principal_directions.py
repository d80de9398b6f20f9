"""Beyond the print: the FPD angle of Eqs 18-20 from the real tooth surfaces' principal directions.

The paper defines xi (Eqs 18-21) as the crossing angle of the first principal directions of the
two tooth surfaces and computes it from the contact lines of each member with the common rack
(Eqs 19-20: the member axis projected onto the rack's flank plane, k = a - (a.N)N).

This model closes the gap with the surfaces themselves.  For every registered tooth-surface
model and flank it takes the derived fundamental forms (the ones the curvature kernels are
generated from, ``kernels.fundamental_forms``), and checks, at 50 digits at random points of the
domain (any l, u, rack data and pitch radius), that the member axis projected onto the tangent
plane, k = a - (a.n)n, is a principal direction of curvature zero:

    II (I^-1 R_D^T k) = 0     (residual relative to |II| |adj I| |R_D^T k|).

At the pitch point P the tangent plane of both flanks is the common rack's flank plane (the
contact normal is the rack normal there), so the crossing angle of the two zero-curvature
principal directions is the angle between the two axes projected on that plane: exactly the
derived form of Eq 18, which is checked against the printed Eqs 18-20 above.  A model whose
flanks are not developable with rulings along the projected axis (a crowned flank) shows a
non-zero residual here: how far off is the number reported.
"""
from __future__ import annotations

import random

import mpmath
import sympy as sp

from .common import DIGITS, N_POINTS, REL_TOL, CheckResult, uniform, uniform_deg
from .symbols import a, alpha_n, b, beta, gamma, l, r, s, u

LABEL = "FPD-principal-directions"
TITLE = "FPD angle: rack contact lines are the zero-curvature principal directions"


def residual(model, sigma):
    """(relative residual Matrix(2), its symbols) for one model and flank."""
    from .kernels import fundamental_forms

    p, n, _ = model.tooth_surface(sigma)
    jac = p.jacobian([l, u])
    hess = sp.Matrix([[p[i].diff(l, 2), p[i].diff(l, u), p[i].diff(u, 2)] for i in range(3)])
    first, second = fundamental_forms(jac, hess, n)
    axis = sp.Matrix([0, 0, 1])
    k = axis - axis.dot(n) * n
    rhs = jac.T * k
    adj = first.adjugate()
    res = second * adj * rhs
    return res, (second.norm() * adj.norm() * rhs.norm())


def _sample(rng, syms, model):
    keys = getattr(model, "KEYS", {})
    fields = {f.symbol: f.name for f in getattr(model, "PARAMETERS", ())}
    base = {l: uniform(rng, 0.5, 20), u: uniform(rng, -40, 40), alpha_n: uniform_deg(rng, 14, 30),
            beta: uniform_deg(rng, -45, 45), gamma: uniform_deg(rng, -8, 8), a: uniform(rng, 1, 15),
            b: uniform(rng, 1, 10), s: uniform(rng, -5, 5), r: uniform(rng, 20, 400)}
    out = []
    for x in syms:
        if x in base:
            out.append(base[x])
        elif fields.get(x) in keys:
            _d, lo, hi = keys[fields[x]]
            out.append(uniform(rng, lo, hi))
        else:  # a member quantity filled from the design (face width, module): a plausible range
            out.append(uniform(rng, 2, 60))
    return out


def check(models=None, seed=20130021):
    """One CheckResult per model (both flanks), equation label LABEL[:model]."""
    from .eq01_03_rack_cutter import LEFT, RIGHT
    from .kernels import SURFACE_MODELS

    results = []
    for name, model in (models or SURFACE_MODELS).items():
        rng = random.Random(seed)
        worst = mpmath.mpf(0)
        for sigma in (LEFT, RIGHT):
            res, scale = residual(model, sigma)
            syms = sorted(set().union(*[e.free_symbols for e in list(res) + [scale]]), key=str)
            f = sp.lambdify(syms, [res[0], res[1], scale], modules="mpmath", cse=True)
            with mpmath.workdps(DIGITS):
                for _ in range(N_POINTS):
                    r0, r1, sc = f(*_sample(rng, syms, model))
                    worst = max(worst, mpmath.sqrt(r0 ** 2 + r1 ** 2) / sc)
        ok = worst < REL_TOL
        note = ("The contact line of each member with the common rack (Eqs 19-20) is the zero-curvature "
                "principal direction of its flank at every point, so Eq 18's crossing angle is the crossing "
                "angle of the first principal directions at P." if ok else
                f"On '{name}' flanks the projected axis is not a zero-curvature principal direction: "
                f"Eqs 18-20 do not give the crossing angle of the principal directions (relative residual {float(worst):.1e}).")
        results.append(CheckResult(f"{LABEL}:{name}", f"{TITLE} ('{name}' flanks)", "verified" if ok else "differs",
                                   f"50-digit at {N_POINTS} points per flank", float(worst), note))
    return results

"""Face coupling of the loaded TCA's tooth beams: a cantilever plate strip per Fourier mode (issue 23).

The LTCA takes each tooth as thin slices (cantilever beams, beveloid/ltca/mechanics/tooth_compliance.py);
neighbouring slices are coupled because the tooth is a plate: a load at one face position bends
the tooth over a length of the order of its height.  Here the tooth is a Kirchhoff plate of
uniform bending stiffness D, height h (root x = 0 to tip x = h) and, for the coupling only,
infinite extent along the face z.  Under an edge line load q cos(k z) at the tip the deflection is
w = f(x) cos(k z) with

    f'''' - 2 k^2 f'' + k^4 f = 0          (D nabla^4 w = 0)
    f = A cosh(k x) + B sinh(k x) + C x cosh(k x) + E x sinh(k x)
    f(0) = 0,  f'(0) = 0                    (clamped root)
    f''(h) - nu k^2 f(h) = 0               (free edge: no bending moment M_x)
    -D (f'''(h) - (2 - nu) k^2 f'(h)) = q   (Kirchhoff edge shear V_x carries the load)

and the edge compliance per mode is C(k) = f(h) / q.  At k = 0 it is the beam's h^3 / (3 D), so
the ratio R(t) = C(k) / C(0), t = k h, is the plate's transfer function of the slice compliance:

    R(t) = 3 (sinh 2t - 2t) / (t^3 [(1 - nu)(3 + nu) sinh^2 t + (1 - nu)^2 t^2 + 4]),

R(0) = 1, R = 1 + (nu - 4/5) t^2 + O(t^4) (a string on an elastic foundation with coupling
length h sqrt(4/5 - nu) has the same first term), and R ~ 6 / ((1 - nu)(3 + nu) t^3) for large t:
the free edge of a semi-infinite plate, stiffer to short waves than the string's 1 / (lambda k)^2.

The runtime builds the face coupling of a finite face 0 <= z <= L with free ends (w' = 0 there) as
the cosine series  G(z, z') = (1/L) sum_n eps_n R(k_n h) cos(k_n z) cos(k_n z'),  k_n = n pi / L,
eps_0 = 1, eps_n = 2: int G dz' = 1, so a uniform line load still gives exactly the thin-slice
deflection (the mesh stiffness is unchanged) and only the load's distribution along the face
feels the plate.  The slices carry the real (tapered, involute) section; the plate's uniform
thickness enters only through this ratio.

Printed forms: ``edge_compliance_ratio`` is written with exp(-2t) so that it neither overflows
nor loses digits for large t; ``edge_compliance_ratio_series`` (to t^6) is for small t, where the
closed form cancels (tests hold both to the solved boundary-value problem).
"""
import sympy as sp

t = sp.Symbol("t", positive=True)  # k h: wave number along the face times the plate height
nu = sp.Symbol("nu", positive=True)  # Poisson's ratio
x, k, h, q, D = sp.symbols("x k h q D", positive=True)


def strip_deflection():
    """f(x) solved from the plate equation and the four edge conditions (q and D symbolic)."""
    A, B, C, E = sp.symbols("A B C E")
    f = A * sp.cosh(k * x) + B * sp.sinh(k * x) + C * x * sp.cosh(k * x) + E * x * sp.sinh(k * x)
    d = [sp.diff(f, x, n) for n in range(4)]
    conditions = [d[0].subs(x, 0), d[1].subs(x, 0), (d[2] - nu * k ** 2 * d[0]).subs(x, h),
                  (-D * (d[3] - (2 - nu) * k ** 2 * d[1])).subs(x, h) - q]
    (sol,) = sp.solve(conditions, [A, B, C, E], dict=True)
    return f.xreplace(sol)


def plate_equation_residual(f):
    """D nabla^4 (f cos kz) / cos kz: zero for a solution of the plate equation."""
    return sp.diff(f, x, 4) - 2 * k ** 2 * sp.diff(f, x, 2) + k ** 4 * f


def solved_ratio():
    """R(t) = f(h) / (q h^3 / (3 D)) with k = t / h, as the boundary-value problem gives it."""
    return sp.simplify((strip_deflection().subs(x, h) / (q * h ** 3 / (3 * D))).subs(k, t / h))


def edge_compliance_ratio():
    """R(t) in the printed closed form, rewritten with e = exp(-2t) (no overflow for large t)."""
    e = sp.exp(-2 * t)
    return 6 * (1 - e ** 2 - 4 * t * e) / (t ** 3 * ((1 - nu) * (3 + nu) * (1 - e) ** 2
                                                     + 4 * e * ((1 - nu) ** 2 * t ** 2 + 4)))


def printed_ratio():
    """R(t) as printed in the module docstring (hyperbolic functions)."""
    return 3 * (sp.sinh(2 * t) - 2 * t) / (t ** 3 * ((1 - nu) * (3 + nu) * sp.sinh(t) ** 2 + (1 - nu) ** 2 * t ** 2 + 4))


def edge_compliance_ratio_series(order=8):
    """R(t) to O(t^order) (even powers only), for small t where the closed form cancels."""
    return sp.collect(sp.expand(sp.series(printed_ratio(), t, 0, order).removeO()), t, sp.factor)


def large_t_limit():
    """t^3 R(t) as t -> infinity: the free edge of a semi-infinite plate."""
    return sp.limit(t ** 3 * edge_compliance_ratio(), t, sp.oo)

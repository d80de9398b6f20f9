"""Hertz contact: elliptical point contact and the 2-D line-contact limit.

Point contact (Johnson, *Contact Mechanics*, 1985, Sec. 4.2).  Near the first contact
point the unloaded gap between the two bodies is h = A x^2 + B y^2 in the principal
axes of relative curvature (A = 1/(2 R_x), B = 1/(2 R_y)).  Under a normal force P the
contact area is an ellipse with semi-axes a >= b, a along the axis of the smaller
coefficient, carrying p = p0 sqrt(1 - (x/a)^2 - (y/b)^2).  With e^2 = 1 - b^2/a^2 and the
complete elliptic integrals K(e), E(e) (modulus e; parameter m = e^2):

    A_small = p0 b (K - E) / (E* e^2 a^2)
    A_large = p0 b ((a/b)^2 E - K) / (E* e^2 a^2)
    delta   = p0 b K / E*                      (approach of distant points)
    P       = 2/3 pi a b p0

The ratio A_large/A_small = ((a/b)^2 E - K)/(K - E) depends on e alone and is solved for
it; then a^3 = 3 P (K - E) / (2 pi E* A_small e^2).

Line contact (two cylinders, parallel axes, load q per unit length, 1/R = 1/R1 + 1/R2):
half-width b = sqrt(4 q R / (pi E*)), p0 = 2 q / (pi b).  The approach of a 2-D contact
is not defined by the local solution (it depends on the bodies' size), so none is given.

Hertz on uncoupled slices (the thin-slice tooth in series with the half-space; derivation in
docs/loaded_contact.md section 5.1).  If the bodies also rest on slices normal to y that deflect
independently by g q(y), q(y) = int p dx the load per unit length, the Hertz pressure of semi-axes
(a_x, a_y) still solves the problem: its line load is q0 (1 - y^2/a_y^2) with q0 = 3 P / (4 a_y),
so the slices add g q0 - (g q0 / a_y^2) y^2, a constant and a smaller curvature along y.  The
contact is Hertz's for A and B_eff = B - 3 g P / (4 a_y^3), with a_y the semi-axis along y of that
same contact (one equation in a_y), and its approach is delta + g q0.
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass

from . import checks

__all__ = [
    "HertzPointContact",
    "HertzLineContact",
    "relative_curvature_coefficients",
    "hertz_point_contact",
    "hertz_line_contact",
    "hertz_point_contact_on_slices",
]


@dataclass(frozen=True)
class HertzPointContact:
    """Hertz elliptical contact: semi-axes (mm), p0 (MPa), approach (mm), eccentricity."""

    semi_major_mm: float
    semi_minor_mm: float
    semi_axis_x_mm: float
    semi_axis_y_mm: float
    max_pressure_mpa: float
    approach_mm: float
    eccentricity: float
    load_n: float

    @property
    def area_mm2(self) -> float:
        return math.pi * self.semi_major_mm * self.semi_minor_mm


@dataclass(frozen=True)
class HertzLineContact:
    """Hertz 2-D contact: half-width (mm) and p0 (MPa) for a load per unit length (N/mm)."""

    half_width_mm: float
    max_pressure_mpa: float
    load_per_length_n_per_mm: float


def relative_curvature_coefficients(
    k1_max_per_mm: float, k1_min_per_mm: float, k2_max_per_mm: float, k2_min_per_mm: float, angle_rad: float
) -> tuple[float, float]:
    """(A, B), A <= B, of the gap h = A x^2 + B y^2 from both bodies' principal curvatures.

    Curvatures are positive where a body is convex (centre of curvature inside it);
    ``angle_rad`` is the angle between the planes of k1_max and k2_max (Johnson Eq. 4.3):
    A + B = (k1_max + k1_min + k2_max + k2_min)/2,
    B - A = sqrt(d1^2 + d2^2 + 2 d1 d2 cos 2 angle)/2, d_i = k_i_max - k_i_min.
    Raises ValueError when A <= 0 (the bodies do not touch at a point from outside).
    """
    vals = [float(v) for v in (k1_max_per_mm, k1_min_per_mm, k2_max_per_mm, k2_min_per_mm, angle_rad)]
    if not all(math.isfinite(v) for v in vals):
        raise ValueError(f"curvatures and angle = {vals!r}: must all be finite")
    k1a, k1b, k2a, k2b, psi = vals
    s = 0.5 * (k1a + k1b + k2a + k2b)
    d1, d2 = k1a - k1b, k2a - k2b
    d = 0.5 * math.sqrt(max(d1 * d1 + d2 * d2 + 2.0 * d1 * d2 * math.cos(2.0 * psi), 0.0))
    a_coef, b_coef = 0.5 * (s - d), 0.5 * (s + d)
    if not a_coef > 0.0:
        raise ValueError(
            f"relative curvature A = {a_coef!r} 1/mm: both coefficients must be > 0 for a point contact"
        )
    return a_coef, b_coef


def _elliptic(q: float) -> tuple[float, float]:
    """(K, E) of the parameter m = 1 - q^2 (0 < q <= 1) by the arithmetic-geometric mean (Abramowitz and Stegun
    17.6.1-17.6.4): a_0 = 1, b_0 = q, c_0^2 = m; a_(n+1) = (a_n + b_n)/2, b_(n+1) = sqrt(a_n b_n), c_(n+1) = (a_n -
    b_n)/2; K = pi / (2 AGM(1, q)), E = K (1 - sum_n 2^(n-1) c_n^2).  Starting from q itself, K stays accurate as
    q -> 0 (scipy.special's ellipkm1(q^2)); within a few units of the rounding of scipy.special's ellipkm1 and ellipe
    (tests/ltca/test_ltca_hertz.py), without importing scipy.special (~0.2 s of a command's CPU, issue 59)."""
    a, b = 1.0, q
    total = 0.5 * (1.0 - q * q)  # 2^-1 c_0^2
    weight = 1.0  # 2^(n-1) for n = 1
    for _ in range(64):
        c = 0.5 * (a - b)
        total += weight * c * c
        weight *= 2.0
        a, b = 0.5 * (a + b), math.sqrt(a * b)
        if a - b <= 1e-15 * a:  # the next c^2 below 1e-30: past the rounding
            break
    k = math.pi / (a + b)
    return k, k * (1.0 - total)


def _ratio(q: float) -> tuple[float, float, float, float]:
    """For b/a = q: (A_large/A_small, K, E, e^2)."""
    m = 1.0 - q * q
    k, e = _elliptic(q)
    return ((e / (q * q) - k) / (k - e)), k, e, m


#: the bracket of ln(b/a) that :func:`_shape` searches (b/a from 1e-8 to 1 - 1e-9)
LOG_Q_RANGE = (math.log(1e-8), math.log(1.0 - 1e-9))


@functools.lru_cache(maxsize=4096)
def _shape(target: float) -> tuple:
    """(b/a, K, E, e^2, (K - E)/e^2) of the contact ellipse of curvature ratio ``target`` >= 1: it does
    not depend on the load (kept per ratio: the LTCA sizes every pair's grid several times).

    ratio(q) falls monotonically from infinity (q -> 0) to 1 (q = 1); its root in t = ln q by Newton's method
    from Hamrock and Brewe's fit a/b = 1.0339 (B/A)^0.636, on the slope d ln(ratio)/dt = (K - 2 E/q^2)/(E/q^2 - K)
    + E/(K - E) (from dK/dm = (E - (1 - m) K)/(2 m (1 - m)), dE/dm = (E - K)/(2 m), m = 1 - q^2), a step that
    leaves the bracket the root is known to lie in replaced by its midpoint; the root to the rounding of t, as
    scipy.optimize.brentq found it before (xtol 1e-15), without importing scipy.optimize (~0.2 s of a command's
    CPU: the tolerance box's own process imports it for nothing else, issue 59)."""
    if target - 1.0 < 1e-12:
        return 1.0, math.pi / 2, math.pi / 2, 0.0, math.pi / 4  # (K - E)/e^2 -> pi/4 as e -> 0
    lo, hi = LOG_Q_RANGE
    goal = math.log(target)
    t = min(max(-0.636 * goal - math.log(1.0339), lo), hi)
    for _ in range(100):
        q = math.exp(t)
        r, k, e, _ = _ratio(q)
        f = math.log(r) - goal
        if f == 0.0:
            break
        if f > 0.0:  # the ratio too large: q too small
            lo = t
        else:
            hi = t
        iq2 = 1.0 / (q * q)
        step = -f / ((k - 2.0 * e * iq2) / (e * iq2 - k) + e / (k - e))
        nxt = t + step if math.isfinite(step) and lo < t + step < hi else 0.5 * (lo + hi)
        done = abs(nxt - t) < 1e-13 or hi - lo < 1e-15
        t = nxt
        if done:  # the step just taken leaves an error of the order of its square: t to its rounding
            break
    q = math.exp(t)
    _, k, e, m = _ratio(q)
    return q, k, e, m, (k - e) / m


def hertz_point_contact(
    a_coef_per_mm: float, b_coef_per_mm: float, load_n: float, e_star_mpa: float
) -> HertzPointContact:
    """Hertz contact of the gap h = A x^2 + B y^2 (A, B > 0, 1/mm) under ``load_n``.

    ``e_star_mpa`` from :func:`beveloid.ltca.mechanics.halfspace.reduced_modulus_mpa`.
    Valid for ratios max(A, B)/min(A, B) up to 1e10 (b/a down to about 1e-7).
    """
    ax, by = checks.positive("a_coef_per_mm", a_coef_per_mm), checks.positive("b_coef_per_mm", b_coef_per_mm)
    p = checks.positive("load_n", load_n)
    es = checks.positive("e_star_mpa", e_star_mpa)
    small, large = min(ax, by), max(ax, by)
    target = large / small
    if target > 1e10:
        raise ValueError(f"curvature ratio {target!r}: must be <= 1e10 (use hertz_line_contact beyond)")
    q, k, e, m, _ = _shape(target)
    a, b = semi_axes_mm(ax, by, p, es)
    p0 = 3.0 * p / (2.0 * math.pi * a * b)
    delta = p0 * b * k / es
    ax_x, ax_y = (a, b) if ax <= by else (b, a)
    return HertzPointContact(a, b, ax_x, ax_y, p0, delta, math.sqrt(m), p)


def semi_axes_mm(a_coef_per_mm: float, b_coef_per_mm: float, load_n: float, e_star_mpa: float) -> tuple:
    """(semi-major, semi-minor) mm of :func:`hertz_point_contact`'s ellipse, by its arithmetic, for arguments it
    would accept (floats, finite and > 0, the ratio of the coefficients at most 1e10), unchecked: the LTCA
    sizes every pair's grid by it (ltca.model.grid.hertz_semi_axes, thousands of pairs a call)."""
    small, large = min(a_coef_per_mm, b_coef_per_mm), max(a_coef_per_mm, b_coef_per_mm)
    q, _, _, _, k_minus_e_over_m = _shape(large / small)
    a = (3.0 * load_n * k_minus_e_over_m / (2.0 * math.pi * e_star_mpa * small)) ** (1.0 / 3.0)
    return a, q * a


def hertz_line_contact(radius_mm: float, load_per_length_n_per_mm: float, e_star_mpa: float) -> HertzLineContact:
    """Hertz 2-D contact of relative radius R (1/R = 1/R1 + 1/R2) under q (N/mm)."""
    r = checks.positive("radius_mm", radius_mm)
    q = checks.positive("load_per_length_n_per_mm", load_per_length_n_per_mm)
    es = checks.positive("e_star_mpa", e_star_mpa)
    b = math.sqrt(4.0 * q * r / (math.pi * es))
    return HertzLineContact(b, 2.0 * q / (math.pi * b), q)


def hertz_point_contact_on_slices(
    a_coef_per_mm: float, b_coef_per_mm: float, load_n: float, e_star_mpa: float, slice_compliance_mm2_per_n: float
) -> HertzPointContact:
    """Hertz contact of h = A x^2 + B y^2 whose bodies also rest on uncoupled slices along y.

    A slice at y deflects by g q(y) (g = ``slice_compliance_mm2_per_n``, mm per N/mm; q the
    load per unit length along y).  The result is the Hertz contact of (A, B_eff) with
    B_eff = B - 3 g P / (4 a_y^3) solved for its own a_y; ``approach_mm`` includes the
    slices' g q0.  g = 0 is :func:`hertz_point_contact`.
    """
    ax, by = checks.positive("a_coef_per_mm", a_coef_per_mm), checks.positive("b_coef_per_mm", b_coef_per_mm)
    p = checks.positive("load_n", load_n)
    es = checks.positive("e_star_mpa", e_star_mpa)
    g = float(slice_compliance_mm2_per_n)
    if not (math.isfinite(g) and g >= 0.0):
        raise ValueError(f"slice_compliance_mm2_per_n = {slice_compliance_mm2_per_n!r}: must be a finite number >= 0")
    if g == 0.0:
        return hertz_point_contact(ax, by, p, es)
    c = 0.75 * g * p

    def contact(a_y: float) -> HertzPointContact:
        return hertz_point_contact(ax, by - c / a_y**3, p, es)

    # B_eff runs from 0+ (a_y at lo: the contact's own a_y is longer) up to B (a_y -> infinity:
    # shorter); the curvature ratio stays inside hertz_point_contact's 1e10
    lo = (c / (by * (1.0 - min(0.5, max(1e-6, 1e-9 * ax / by))))) ** (1.0 / 3.0)
    hi = max(2.0 * lo, 2.0 * hertz_point_contact(ax, by, p, es).semi_axis_y_mm)
    while contact(hi).semi_axis_y_mm > hi:
        hi *= 2.0
    from scipy.optimize import brentq  # here, not at import: scipy.optimize costs every command ~0.3 s
    a_y = brentq(lambda t: contact(t).semi_axis_y_mm - t, lo, hi, xtol=1e-14, rtol=1e-13, maxiter=200)
    h = contact(a_y)
    q0 = 0.75 * p / h.semi_axis_y_mm
    return HertzPointContact(h.semi_major_mm, h.semi_minor_mm, h.semi_axis_x_mm, h.semi_axis_y_mm,
                             h.max_pressure_mpa, h.approach_mm + g * q0, h.eccentricity, p)

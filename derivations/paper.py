"""The paper's printed forms, typed from ../shared/paper/equations.md (a clean reading of the print).

Nothing here is derived: these expressions are what the models are held against.
Where the print has an upper/lower sign, ``upper`` is the left flank (Eqs 1-3 wording).
"""
import sympy as sp

from .symbols import (
    E, N1, N2, a, alpha_PL, alpha_PL1, alpha_PL2, alpha_PR, alpha_PR1, alpha_PR2, alpha_PwL, alpha_PwL1,
    alpha_PwL2, alpha_PwR, alpha_PwR1, alpha_PwR2, alpha_n, alpha_nw, b, b_c1, b_c2, beta, beta1, beta2, beta_w,
    beta_w1, beta_w2, d_w1, d_w2, delta, dg_h, dg_v, dx_q, dy_q, dz_q, gamma, gamma1, gamma2, gamma_w, gamma_w1,
    gamma_w2, inv, l, m_n, m_nw, n_xc, n_yc, phi, phi1p, phi2p, r, r_w1, r_w2, theta, u, u_c, x_c, x_t1, x_t2, xi_n,
    xi_t, y_c, z_c,
)

sin, cos, tan, sqrt, acos = sp.sin, sp.cos, sp.tan, sp.sqrt, sp.acos


# Eqs 1-3: rack cutter, upper sign = left straight edge
def eq01_03(sign):
    h = l * sin(alpha_n) - a * tan(alpha_n) - b
    xc = (l * cos(alpha_n) - a) * cos(gamma) + (-sign * h * sin(beta) + u * cos(beta)) * sin(gamma)
    yc = sign * h * cos(beta) + u * sin(beta)
    zc = -(l * cos(alpha_n) - a) * sin(gamma) + (-sign * h * sin(beta) + u * cos(beta)) * cos(gamma)
    return sp.Matrix([xc, yc, zc])


# Eqs 4-6 (in terms of the cutter point), Eq 7 meshing equation
eq04_06 = sp.Matrix([
    x_c * cos(phi) - y_c * sin(phi) + r * (cos(phi) + phi * sin(phi)),
    x_c * sin(phi) + y_c * cos(phi) + r * (sin(phi) - phi * cos(phi)),
    z_c,
])
eq07 = (n_xc * y_c - n_yc * x_c) / (n_xc * r)

# Eq 8-9: pitch cone and its unit normal
eq08 = sp.Matrix([u_c * sin(gamma_w) * cos(theta), u_c * sin(gamma_w) * sin(theta), u_c * cos(gamma_w)])
eq09 = sp.Matrix([cos(theta) * cos(gamma_w), sin(theta) * cos(gamma_w), -sin(gamma_w)])

# Eqs 12-14
S = sqrt(sin(delta) ** 2 - sin(gamma_w1) ** 2 - sin(gamma_w2) ** 2 - 2 * sin(gamma_w1) * sin(gamma_w2) * cos(delta))
eq12 = E * cos(gamma_w1) * sin(delta) / S - r_w2 * cos(gamma_w1) / cos(gamma_w2)
eq13 = (E * (sin(delta) ** 2 - sin(gamma_w1) ** 2 - sin(gamma_w1) * sin(gamma_w2) * cos(delta)) / (sin(gamma_w1) * sin(delta) * S)
        - r_w2 / (sin(gamma_w1) * cos(gamma_w2)))
eq14 = (E * (sin(delta) ** 2 - sin(gamma_w2) ** 2 - sin(gamma_w1) * sin(gamma_w2) * cos(delta)) / (sin(gamma_w2) * sin(delta) * S)
        - r_w1 / (sin(gamma_w2) * cos(gamma_w1)))

# Eq 16 (printed: cos(beta_w1 +- beta_w2) = ...); we record the right-hand side and the "+" reading
eq16_rhs = tan(gamma_w1) * tan(gamma_w2) + cos(delta) / (cos(gamma_w1) * cos(gamma_w2))
eq16_plus = acos(eq16_rhs)  # beta_w1 + beta_w2 with the "+" sign

# Eq 17 ("+" reading)
eq17 = (r_w1 * cos(gamma_w2) + r_w2 * cos(gamma_w1)) * sin(beta_w1 + beta_w2) / sin(delta)

# Eqs 18-20: FPD angles (per gear), returned as tan xi
eq19_tan = tan(beta_w) * sin(alpha_nw) + tan(gamma_w) * cos(alpha_nw) / cos(beta_w)
eq20_tan = tan(beta_w) * sin(alpha_nw) - tan(gamma_w) * cos(alpha_nw) / cos(beta_w)

# Eq 22-26 (single gear; r is the reference pitch radius)
eq22_ratio_L = cos(alpha_PwL) / cos(alpha_PL)
eq22_ratio_R = cos(alpha_PwR) / cos(alpha_PR)
eq23_xi_n_modules = m_n / m_nw
eq23_xi_n_angles = cos(alpha_nw) / cos(alpha_n)
eq23_xi_n_transverse = xi_t * cos(beta) / cos(beta_w)
eq24_tan_gamma_w = 2 * tan(alpha_n) * sin(gamma) / cos(beta) / (xi_t * (tan(alpha_PwR) + tan(alpha_PwL)))
eq25_sin_gamma_w_a = sin(gamma) * tan(alpha_n) / (xi_n * tan(alpha_nw))
eq25_sin_gamma_w_b = sin(gamma) * sin(alpha_n) / sin(alpha_nw)
eq26_sin_beta_w = sin(beta) * cos(gamma) / (xi_n * cos(gamma_w))

# Eq 27 backlash-free condition, written as lhs - rhs
eq27_lhs = 2 * tan(alpha_n) * (x_t1 * cos(gamma1) / cos(beta1) + x_t2 * cos(gamma2) / cos(beta2))
eq27_rhs = (N1 / 2 * (inv(alpha_PwL1) + inv(alpha_PwR1) - inv(alpha_PL1) - inv(alpha_PR1))
            + N2 / 2 * (inv(alpha_PwL2) + inv(alpha_PwR2) - inv(alpha_PL2) - inv(alpha_PR2)))

# Eqs 30-35: transforms
eq30 = sp.Matrix([[cos(phi1p), -sin(phi1p), 0, 0], [sin(phi1p), cos(phi1p), 0, 0], [0, 0, 1, d_w1 - b_c1], [0, 0, 0, 1]])
eq31 = eq30[:3, :3]
eq33 = sp.Matrix([[1, 0, 0, E], [0, cos(delta), sin(delta), sin(delta) * (d_w2 - b_c2)],
                  [0, -sin(delta), cos(delta), cos(delta) * (d_w2 - b_c2)], [0, 0, 0, 1]])
_mq = sp.Matrix([
    [cos(dg_v), 0, sin(dg_v), dx_q],
    [-sin(dg_v) * sin(dg_h), cos(dg_h), sin(dg_h) * cos(dg_v), dy_q],
    [-sin(dg_v) * cos(dg_h), -sin(dg_h), cos(dg_h) * cos(dg_v), dz_q],
    [0, 0, 0, 1]])
_rz2 = sp.Matrix([[cos(phi2p), -sin(phi2p), 0, 0], [sin(phi2p), cos(phi2p), 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])
eq34 = _mq * _rz2
eq32 = eq33 * eq34
eq35 = eq33[:3, :3] * _mq[:3, :3] * _rz2[:3, :3]

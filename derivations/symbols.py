"""The paper's symbols, shared by the models and by paper.py (names follow the paper)."""
import sympy as sp

R = dict(real=True)
P = dict(positive=True)

# rack cutter (Eqs 1-3) and generation (Eqs 4-7)
l, u = sp.symbols("l u", **R)                       # surface parameters (mm)
alpha_n = sp.Symbol("alpha_n", **P)                 # normal pressure angle (rad)
beta = sp.Symbol("beta", **R)                       # helix angle, signed: RH +
gamma = sp.Symbol("gamma", **R)                     # cone angle (rad)
a, b = sp.symbols("a b", **P)                       # cutter addendum, half tooth thickness (mm)
s = sp.Symbol("s", **R)                             # rack shift along its own depth axis (mm)
x_c, y_c, z_c = sp.symbols("x_c y_c z_c", **R)      # cutter point (Eqs 4-6 written in them)
n_xc, n_yc, n_zc = sp.symbols("n_xc n_yc n_zc", **R)
phi = sp.Symbol("phi", **R)                         # generating roll angle (rad)
r = sp.Symbol("r", **P)                             # generating pitch radius (mm)
m_n = sp.Symbol("m_n", **P)
N = sp.Symbol("N", **P)
x_t = sp.Symbol("x_t", **R)                         # transverse profile-shift coefficient

# pitch cones (Eqs 8-17)
theta, u_c = sp.symbols("theta u_cone", **R)
theta1, theta2 = sp.symbols("theta1 theta2", **R)
u1, u2 = sp.symbols("u1 u2", **P)
gamma_w, gamma_w1, gamma_w2 = sp.symbols("gamma_w gamma_w1 gamma_w2", **R)
delta = sp.Symbol("delta", **P)                     # shaft angle
E = sp.Symbol("E", **P)                             # offset
r_w1, r_w2 = sp.symbols("r_w1 r_w2", **P)
d1, d2 = sp.symbols("d1 d2", **R)
beta_w, beta_w1, beta_w2 = sp.symbols("beta_w beta_w1 beta_w2", **R)
eta = sp.Symbol("eta", **R)
alpha_nw = sp.Symbol("alpha_nw", **P)

# reference/working data (Eqs 22-27)
r_w = sp.Symbol("r_w", **P)
xi_t, xi_n = sp.symbols("xi_t xi_n", **P)
m_nw = sp.Symbol("m_nw", **P)
alpha_PL, alpha_PR, alpha_PwL, alpha_PwR = sp.symbols("alpha_PL alpha_PR alpha_PwL alpha_PwR", **R)
N1, N2 = sp.symbols("N1 N2", **P)
beta1, beta2, gamma1, gamma2 = sp.symbols("beta1 beta2 gamma1 gamma2", **R)
x_t1, x_t2 = sp.symbols("x_t1 x_t2", **R)
alpha_PL1, alpha_PR1, alpha_PwL1, alpha_PwR1 = sp.symbols("alpha_PL1 alpha_PR1 alpha_PwL1 alpha_PwR1", **R)
alpha_PL2, alpha_PR2, alpha_PwL2, alpha_PwR2 = sp.symbols("alpha_PL2 alpha_PR2 alpha_PwL2 alpha_PwR2", **R)

# meshing model (Eqs 28-38)
phi1p, phi2p = sp.symbols("phi1p phi2p", **R)       # phi'_1, phi'_2
d_w1, d_w2, b_c1, b_c2 = sp.symbols("d_w1 d_w2 b_c1 b_c2", **R)
dx_q, dy_q, dz_q = sp.symbols("Delta_x_q Delta_y_q Delta_z_q", **R)
dg_v, dg_h = sp.symbols("Delta_gamma_v Delta_gamma_h", **R)
l1, l2 = sp.symbols("l1 l2", **R)
uu1, uu2 = sp.symbols("u_1 u_2", **R)               # tooth-surface u of pinion and gear


def inv(x):
    """Involute function inv(x) = tan x - x."""
    return sp.tan(x) - x

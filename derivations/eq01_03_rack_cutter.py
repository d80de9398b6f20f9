"""Eqs 1-3: the rack cutter, as a product of elementary transforms.

The straight edge of the normal section, l measured from M0 (the rack tip corner):

    x_n = l cos(alpha_n) - a + s,   Y = sigma * h,   h = l sin(alpha_n) - a tan(alpha_n) - b

sigma = +1 is the paper's upper sign (left edge), -1 the lower sign (right edge).
The normal section is turned by the helix angle about the depth axis (u runs along the
tooth) and the rack is tilted by the cone angle about the pitch-line direction y:

    R_c = R_y(gamma) R_x(-beta) [x_n, Y, u]

``s`` is the rack's shift along its own depth axis; the paper prints Eqs 1-3 with s = 0.
The transverse profile shift x_t of Table 1 puts the rack's pitch plane x_t m_t outside
the generating pitch cylinder in the reference transverse section (z_c = 0), which is
s = x_t m_n cos(gamma) / cos(beta) along the tilted depth axis (see ``rack_shift``).
"""
import sympy as sp

from . import paper
from .common import Equation, rot_x, rot_y, uniform, uniform_deg
from .symbols import a, alpha_n, b, beta, gamma, l, m_n, s, u, x_t

LEFT, RIGHT = 1, -1  # paper's upper / lower sign


def normal_section_point(sigma):
    h = l * sp.sin(alpha_n) - a * sp.tan(alpha_n) - b
    return sp.Matrix([l * sp.cos(alpha_n) - a + s, sigma * h, u])


def rack_rotation():
    """Rotation from the normal-section frame to the cutter frame S_c."""
    return rot_y(gamma)[:3, :3] * rot_x(-beta)[:3, :3]


def rack_point(sigma):
    """Eqs 1-3 (with the depth shift s)."""
    return rack_rotation() * normal_section_point(sigma)


def rack_normal(sigma):
    """Unit normal of the cutter surface, pointing out of the generated tooth's material.

    Equal to sigma * (dR/dl x dR/du): in the normal section the generated tooth occupies
    |Y| < |h|, so its outward normal has the Y component -sigma cos(alpha_n).
    In the normal section that is (sin alpha_n, -sigma cos alpha_n, 0); tests hold it
    against sigma * (dR/dl x dR/du), which is already unit length.
    """
    return rack_rotation() * sp.Matrix([sp.sin(alpha_n), -sigma * sp.cos(alpha_n), 0])


def rack_shift():
    """Depth shift s that puts the pitch plane x_t*m_t outside the pitch cylinder at z_c = 0."""
    return x_t * m_n * sp.cos(gamma) / sp.cos(beta)


def sampler(rng):
    return {
        l: uniform(rng, 0, 20), u: uniform(rng, -40, 40), alpha_n: uniform_deg(rng, 14, 30),
        beta: uniform_deg(rng, -45, 45), gamma: uniform_deg(rng, -8, 8), a: uniform(rng, 1, 15),
        b: uniform(rng, 1, 10), s: 0,
    }


def equations():
    steps = [
        r"Normal section of the straight edge: $x_n = l\cos\alpha_n - a + s$, "
        r"$Y = \pm(l\sin\alpha_n - a\tan\alpha_n - b)$, $u$ along the tooth.",
        r"$R_c = R_y(\gamma)\,R_x(-\beta)\,[x_n, Y, u]^T$; with $s=0$:",
    ]
    eqs = []
    for k, (num, title) in enumerate([(1, "rack cutter x_c"), (2, "rack cutter y_c"), (3, "rack cutter z_c")]):
        derived = [rack_point(sg)[k].subs(s, 0) for sg in (LEFT, RIGHT)]
        printed = [paper.eq01_03(sg)[k] for sg in (LEFT, RIGHT)]
        eqs.append(Equation(
            num, title, "derived", printed=printed, derived=derived, sampler=sampler, symbolic=True,
            steps=steps + [r"$%s = %s$ (upper sign)" % ("xyz"[k] + "_c", sp.latex(derived[0]))],
            note=("Profile shift is not in the print: the model adds the depth shift "
                  "s = x_t m_n cos(gamma)/cos(beta) to x_n (pitch plane x_t m_t outside the pitch cylinder at z_c = 0).")
            if k == 0 else "",
        ))
    return eqs

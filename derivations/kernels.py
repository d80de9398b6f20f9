"""Registry of generated modules: which numeric kernels come from which model.

To try a model variant (another rack profile, another cutter), write a derivation module
that provides the same ``tooth_surface(sigma)`` interface and point the entries below at it;
``beveloid derive`` regenerates the kernels and the solvers pick them up unchanged.
"""
from __future__ import annotations

import sympy as sp

from . import design_chain, eq04_07_tooth_surface, eq28_38_meshing_model
from .codegen import Arg, Function, ModuleSpec, Output
from .eq01_03_rack_cutter import LEFT, RIGHT
from .symbols import (
    E, N1, N2, a, alpha_n, alpha_nw, b, b_c1, b_c2, beta, beta1, beta_w1, d_w1, d_w2, delta, dg_h, dg_v, dx_q, dy_q,
    dz_q, gamma, gamma1, gamma2, gamma_w1, gamma_w2, l, l1, l2, m_n, phi1p, phi2p, r, s, u, uu1, uu2, x_t1,
)

# The surface model used for both members.  A variant model only has to provide
# tooth_surface(sigma) -> (point, outward unit normal, roll angle) in (l, u).
SURFACE_MODEL = eq04_07_tooth_surface
SURFACE_SOURCE = "eq04_07_tooth_surface.py"

FLANKS = (("left", LEFT), ("right", RIGHT))


def _rack_args(suffix=""):
    return [
        Arg("normal_pressure_angle", alpha_n, "rad", "normal pressure angle of the rack, alpha_n"),
        Arg("helix_angle" + suffix, beta, "rad", "helix angle beta (signed, right hand +)"),
        Arg("cone_angle" + suffix, gamma, "rad", "cone angle gamma"),
        Arg("cutter_addendum" + suffix, a, "mm", "cutter addendum a below the rack pitch line"),
        Arg("half_thickness", b, "mm", "half tooth thickness on the rack pitch line, b"),
        Arg("rack_shift" + suffix, s, "mm", "rack shift along its depth axis, x_t m_n cos(gamma)/cos(beta)"),
        Arg("pitch_radius" + suffix, r, "mm", "generating (reference) pitch radius r"),
    ]


def tooth_surface_module():
    fns = []
    lu = [Arg("l", l, "mm", "profile parameter along the rack edge"), Arg("u", u, "mm", "parameter along the tooth")]
    for name, sigma in FLANKS:
        p, n, ph = SURFACE_MODEL.tooth_surface(sigma)
        jac = p.jacobian([l, u])
        hess = sp.Matrix([[p[i].diff(l, 2), p[i].diff(l, u), p[i].diff(u, 2)] for i in range(3)])
        fns.append(Function(
            f"surface_{name}", f"Tooth surface of the {name} flank (Eqs 1-7) in the member frame S_i.",
            lu + _rack_args(),
            [Output("point", p, "mm", "surface point [x, y, z]"),
             Output("normal", n, "1", "unit normal, outward from the tooth"),
             Output("roll_angle", ph, "rad", "generating roll angle phi(l, u) of Eq 7")]))
        fns.append(Function(
            f"surface_derivatives_{name}", f"First and second derivatives of the {name} flank w.r.t. (l, u).",
            lu + _rack_args(),
            [Output("point_D_lu", jac, "mm/mm", "[dR/dl, dR/du] as columns"),
             Output("point_D2_lu", hess, "mm/mm^2", "[d2R/dl2, d2R/dldu, d2R/du2] as columns")]))
    return ModuleSpec("tooth_surface", SURFACE_SOURCE,
                      "Tooth surfaces of the rack-generated beveloid flanks and their derivatives (Eqs 1-7).", fns,
                      scalar_twin=True)


def _pair_args():
    return [
        Arg("normal_module", m_n, "mm", "normal module m_n"),
        Arg("normal_pressure_angle", alpha_n, "rad", "normal pressure angle alpha_n"),
        Arg("pinion_teeth", N1, "1", "pinion tooth number N1"),
        Arg("gear_teeth", N2, "1", "gear tooth number N2"),
        Arg("shaft_angle", delta, "rad", "shaft angle delta"),
        Arg("pinion_profile_shift", x_t1, "1", "pinion transverse profile-shift coefficient x_t1"),
    ]


_DESIGN_OUTPUTS = [
    ("xi_n", "1", "normal angular factor (Eq 23)"),
    ("gamma_w1", "rad", "pinion working cone angle (Eq 25)"), ("gamma_w2", "rad", "gear working cone angle (Eq 25)"),
    ("beta_w1", "rad", "pinion working helix angle (Eq 26)"), ("beta_w2", "rad", "gear working helix angle (Eq 16)"),
    ("beta1", "rad", "pinion helix angle"), ("beta2", "rad", "gear helix angle (Eq 26)"),
    ("gamma1", "rad", "pinion cone angle"), ("gamma2", "rad", "gear cone angle"),
    ("r1", "mm", "pinion reference pitch radius"), ("r2", "mm", "gear reference pitch radius"),
    ("xi_t1", "1", "pinion transverse angular factor (Eq 22-23)"), ("xi_t2", "1", "gear transverse angular factor"),
    ("r_w1", "mm", "pinion working pitch radius"), ("r_w2", "mm", "gear working pitch radius"),
    ("E", "mm", "offset from Eq 17"),
    ("d1", "mm", "pinion mounting distance (Eq 13)"), ("d2", "mm", "gear mounting distance (Eq 14)"),
    ("d_w1", "mm", "pinion working mounting distance: axial position of P from the common perpendicular"),
    ("d_w2", "mm", "gear working mounting distance"),
    ("cos_theta1", "1", "pitch point angle on the pinion cone"), ("sin_theta1", "1", ""),
    ("cos_theta2", "1", "pitch point angle on the gear cone"), ("sin_theta2", "1", ""),
    ("xi_L1", "rad", "pinion FPD angle, left (Eq 19)"), ("xi_L2", "rad", "gear FPD angle, left"),
    ("xi_L", "rad", "FPD angle, left (Eq 18)"),
    ("xi_R1", "rad", "pinion FPD angle, right (Eq 20)"), ("xi_R2", "rad", "gear FPD angle, right"),
    ("xi_R", "rad", "FPD angle, right (Eq 18)"),
    ("alpha_PL1", "rad", "pinion transverse pressure angle, left, reference"), ("alpha_PR1", "rad", ""),
    ("alpha_PL2", "rad", "gear transverse pressure angle, left, reference"), ("alpha_PR2", "rad", ""),
    ("alpha_PwL1", "rad", "pinion transverse pressure angle, left, working"), ("alpha_PwR1", "rad", ""),
    ("alpha_PwL2", "rad", "gear transverse pressure angle, left, working"), ("alpha_PwR2", "rad", ""),
    ("x_t2", "1", "gear transverse profile-shift coefficient, backlash-free (Eq 27)"),
]


def design_module():
    direct = design_chain.direct()
    indirect = design_chain.indirect()
    anw = Arg("alpha_nw", alpha_nw, "rad", "working normal pressure angle (trial)")
    ref = [Arg("pinion_cone_angle", gamma1, "rad", "gamma1"), Arg("gear_cone_angle", gamma2, "rad", "gamma2"),
           Arg("pinion_helix_angle", beta1, "rad", "beta1 (signed)")]
    work = [Arg("pinion_working_cone_angle", gamma_w1, "rad", "gamma_w1"),
            Arg("gear_working_cone_angle", gamma_w2, "rad", "gamma_w2"),
            Arg("pinion_working_helix_angle", beta_w1, "rad", "beta_w1 (signed)")]
    offset = Arg("offset", E, "mm", "required offset E")

    def outs(d):
        return [Output(k, d[k], unit, doc or k) for k, unit, doc in _DESIGN_OUTPUTS]

    e_res = direct["E"] - E
    return ModuleSpec("design_equations", "design_chain.py",
                      "Pitch-cone design equations (Eqs 12-27) composed for the direct and indirect design.", [
        Function("offset_residual", "Eq 17 offset for a trial alpha_nw minus the required offset, and its derivative.",
                 [anw] + _pair_args() + ref + [offset],
                 [Output("residual", e_res, "mm", "E(alpha_nw) - E"),
                  Output("residual_D_alpha_nw", e_res.diff(alpha_nw), "mm/rad", "d residual / d alpha_nw")]),
        Function("offset_scan", "What the alpha_nw scan needs: the Eq 17 residual and both working pitch radii.",
                 [anw] + _pair_args() + ref + [offset],
                 [Output("residual", e_res, "mm", "E(alpha_nw) - E"),
                  Output("r_w1", direct["r_w1"], "mm", "pinion working pitch radius"),
                  Output("r_w2", direct["r_w2"], "mm", "gear working pitch radius")]),
        Function("direct_design", "All design quantities of the direct design for a given alpha_nw.",
                 [anw] + _pair_args() + ref, outs(direct)),
        Function("indirect_design", "All design quantities from the working data (indirect design).",
                 [anw] + _pair_args() + work, outs(indirect)),
    ])


def tca_module():
    fns = []
    s_p = sp.symbols("beta_1 gamma_1 a_1 s_1 r_1", real=True)
    s_g = sp.symbols("beta_2 gamma_2 a_2 s_2 r_2", real=True)
    unknowns = [l1, uu1, l2, uu2, phi2p]
    errors = [dx_q, dy_q, dz_q, dg_v, dg_h]
    for name, sigma in FLANKS:
        p, n, _ = SURFACE_MODEL.tooth_surface(sigma)
        sub1 = {beta: s_p[0], gamma: s_p[1], a: s_p[2], s: s_p[3], r: s_p[4], l: l1, u: uu1}
        sub2 = {beta: s_g[0], gamma: s_g[1], a: s_g[2], s: s_g[3], r: s_g[4], l: l2, u: uu2}
        p1, n1 = p.subs(sub1, simultaneous=True), n.subs(sub1, simultaneous=True)
        p2, n2 = p.subs(sub2, simultaneous=True), n.subs(sub2, simultaneous=True)
        f = eq28_38_meshing_model.tca_residual(p1, n1, p2, n2)
        args = ([Arg("l1", l1, "mm", "pinion profile parameter"), Arg("u1", uu1, "mm", "pinion lengthwise parameter"),
                 Arg("l2", l2, "mm", "gear profile parameter"), Arg("u2", uu2, "mm", "gear lengthwise parameter"),
                 Arg("gear_angle", phi2p, "rad", "phi'_2 of Eq 34"),
                 Arg("pinion_angle", phi1p, "rad", "phi'_1 of Eq 30")]
                + [Arg("dx_q", dx_q, "mm", "gear offset error along x_f"), Arg("dy_q", dy_q, "mm", "... along y"),
                   Arg("dz_q", dz_q, "mm", "... along z"), Arg("dgamma_v", dg_v, "rad", "vertical angular error"),
                   Arg("dgamma_h", dg_h, "rad", "horizontal angular error")]
                + [Arg("normal_pressure_angle", alpha_n, "rad", "alpha_n"), Arg("half_thickness", b, "mm", "b")]
                + [Arg(nm, sy, un, nm) for nm, sy, un in zip(
                    ("pinion_helix_angle", "pinion_cone_angle", "pinion_cutter_addendum", "pinion_rack_shift",
                     "pinion_pitch_radius"), s_p, ("rad", "rad", "mm", "mm", "mm"))]
                + [Arg(nm, sy, un, nm) for nm, sy, un in zip(
                    ("gear_helix_angle", "gear_cone_angle", "gear_cutter_addendum", "gear_rack_shift",
                     "gear_pitch_radius"), s_g, ("rad", "rad", "mm", "mm", "mm"))]
                + [Arg("offset", E, "mm", "E"), Arg("shaft_angle", delta, "rad", "delta"),
                   Arg("pinion_axial_placement", sp.Symbol("z1"), "mm", "d_w1 - b_c1"),
                   Arg("gear_axial_placement", sp.Symbol("z2"), "mm", "d_w2 - b_c2")])
        f = f.subs({d_w1 - b_c1: sp.Symbol("z1"), d_w2 - b_c2: sp.Symbol("z2")})
        f = f.subs({d_w1: sp.Symbol("z1") + b_c1, d_w2: sp.Symbol("z2") + b_c2})
        fns.append(Function(
            f"residual_{name}", f"Eq 38 for the {name} flank pair, with exact Jacobians.",
            args,
            [Output("residual", f, "mm | 1", "[R_f1 - R_f2 (x, y, z), (n_f1 + n_f2)_x, (n_f1 + n_f2)_z]"),
             Output("residual_D_unknowns", f.jacobian(unknowns), "", "d residual / d (l1, u1, l2, u2, phi'_2)"),
             Output("residual_D_errors", f.jacobian(errors), "", "d residual / d (dx, dy, dz, dgamma_v, dgamma_h)"),
             Output("residual_D_pinion_angle", f.diff(phi1p), "", "d residual / d phi'_1")]))
    return ModuleSpec("tca_system", "eq28_38_meshing_model.py",
                      "The TCA system of Eq 38 (both flank pairs) with exact Jacobians.", fns, scalar_twin=True)


def module_specs():
    return [tooth_surface_module(), design_module(), tca_module()]

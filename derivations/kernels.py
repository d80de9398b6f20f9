"""Registry: which generated kernel comes from which model, and the interfaces they share.

Kernels by concern (each a generated module, with a ``*_scalar`` twin where the solver core
needs one point per call):

* ``surface_<model>``: one per tooth-surface model, per flank: the point and unit normal
  (``surface_<flank>``), with their first derivatives in (l, u) (``surface_jet_<flank>``) and
  the second derivatives of the point (``surface_second_derivatives_<flank>``) and the first
  and second fundamental forms (``surface_fundamental_forms_<flank>``, for the curvatures).  Parameters:
  the layout ``<Model>SurfaceParams`` (the rack-generation data every model shares, then the
  model's own fields).
* ``placement``: Eqs 30-35, the pinion and the gear (with the five errors) in S_f.
* ``contact_system``: Eq 38 assembled from two surface jets and the placement, with exact
  Jacobians, whatever surface model each member uses.
* ``flank_boundaries``: the blank's margins (form limit, tip, toe, heel) and their derivatives.
* ``design_equations``: Eqs 12-27 composed for the direct and the indirect design.
* glue (``tca_kernels``, ``tca_kernels_scalar``): the per-member model dispatch and the
  composed contact system / margins that the solver core calls by name.

A new tooth-surface model: write a derivation module with ``tooth_surface(sigma)`` returning
(point, outward unit normal, roll angle) in (l, u) over the symbols of Eqs 1-7, plus optionally

* ``PARAMETERS``: its own fields (a tuple of :class:`interface.Field`).  A field named like a
  member quantity the runtime knows (``face_width_mm``, ``normal_module_mm``) is filled from
  the design; every other field is an input key of the member's TOML section;
* ``KEYS``: {field name: (default, lowest, highest)} of those input keys;
* ``CHOICE_KEYS``: {field name: (default choice, {choice: value})} of input keys given by name
  (the spec checks the name, the kernels take the value);
* ``SELECTED_BY``: input keys whose non-zero value selects the model when the TOML does not
  name one;
* ``tooth_surface_late(sigma)``: (point, normal, roll angle, substitute), the surface over
  abstract functions of (l, u) and the function that makes an expression explicit; the
  generator then differentiates the abstract forms and substitutes after (smaller trees,
  faster derivation, better CSE),
* or ``tooth_surface_staged(sigma)``: the same plus ``stages``, named intermediate values
  ((Symbol, explicit expr), ...) that ``substitute`` writes its results over (a model composed
  on another model's jets: codegen.Function.stages),

add it to ``SURFACE_MODELS`` below and run ``beveloid derive``.  The runtime picks it up by
name (``tooth_surface = "<model>"`` in a member's TOML section); nothing in ``beveloid/``
changes.
"""
from __future__ import annotations

import sympy as sp

from . import (
    codegen, crowned_flank, design_chain, edge_contact, eq04_07_tooth_surface, eq28_38_meshing_model, flank_boundaries,
    flank_micro_geometry, patch_clearance, root_fillet, tooth_plate_coupling, tooth_sections,
)
from .codegen import Arg, Function, ModuleSpec, Output
from .interface import Field, Layout
from .eq01_03_rack_cutter import LEFT, RIGHT
from .symbols import (
    E, N1, N2, a, alpha_n, alpha_nw, b, b_c1, b_c2, beta, beta1, beta_w1, d_w1, d_w2, delta, dg_h, dg_v, dx_q,
    dy_q, dz_q, gamma, gamma1, gamma2, gamma_w1, gamma_w2, l, m_n, phi1p, phi2p, r, s, u, x_t1,
)

# name -> derivation module providing tooth_surface(sigma) (and optionally PARAMETERS)
SURFACE_MODELS = {
    "involute": eq04_07_tooth_surface,
    "crowned": crowned_flank,
    "micro_geometry": flank_micro_geometry,
}

FLANKS = (("left", LEFT), ("right", RIGHT))

# What every rack-generated model takes, named as the runtime's member data.
RACK_FIELDS = (
    Field("normal_pressure_angle", alpha_n, "rad", "normal pressure angle of the rack, alpha_n"),
    Field("helix_angle", beta, "rad", "helix angle beta (signed, right hand +)"),
    Field("cone_angle", gamma, "rad", "cone angle gamma"),
    Field("cutter_addendum_mm", a, "mm", "cutter addendum a below the rack pitch line"),
    Field("half_thickness_mm", b, "mm", "half tooth thickness on the rack pitch line, b"),
    Field("rack_shift_mm", s, "mm", "rack shift along its depth axis, x_t m_n cos(gamma)/cos(beta)"),
    Field("pitch_radius_mm", r, "mm", "generating (reference) pitch radius r"),
)

#: the rack fields whose sin, cos and tan every surface layout carries precomputed (Layout trig)
RACK_ANGLES = ("normal_pressure_angle", "helix_angle", "cone_angle")

ERRORS = Layout("AssemblyErrors", "The five assembly errors of Eq 34 (frame S_q of the aligned gear).", (
    Field("dx_mm", dx_q, "mm", "gear offset error along x_q (the common perpendicular)"),
    Field("dy_mm", dy_q, "mm", "gear offset error along y_q"),
    Field("dz_mm", dz_q, "mm", "gear offset error along z_q (the gear axis)"),
    Field("vertical_rad", dg_v, "rad", "angular error dgamma_v (gear axis turned about y_q)"),
    Field("horizontal_rad", dg_h, "rad", "angular error dgamma_h (gear axis turned about x_q)"),
))

_z1, _z2 = sp.symbols("z_1 z_2", real=True)
PLACEMENT = Layout("PairPlacement", "Where the two members sit in S_f (Eqs 30, 33).", (
    Field("offset_mm", E, "mm", "offset E between the crossed axes"),
    Field("shaft_angle", delta, "rad", "shaft angle delta"),
    Field("pinion_axial_placement_mm", _z1, "mm", "d_w1 - b_c1: the S_1 origin on the pinion axis"),
    Field("gear_axial_placement_mm", _z2, "mm", "d_w2 - b_c2: the S_2 origin on the gear axis"),
), trig=("shaft_angle",))

CONTACT_UNKNOWNS = Layout("ContactUnknowns", "The unknowns of Eq 38 for a given pinion angle, in the solver's order.", (
    Field("pinion_l_mm", sp.Symbol("l_1", real=True), "mm", "pinion profile parameter l"),
    Field("pinion_u_mm", sp.Symbol("u_1", real=True), "mm", "pinion lengthwise parameter u"),
    Field("gear_l_mm", sp.Symbol("l_2", real=True), "mm", "gear profile parameter l"),
    Field("gear_u_mm", sp.Symbol("u_2", real=True), "mm", "gear lengthwise parameter u"),
    Field("gear_angle_rad", phi2p, "rad", "gear rotation phi'_2 of Eq 34"),
))
UNKNOWNS = tuple(f.name for f in CONTACT_UNKNOWNS.fields)
#: one mesh state of a pair: the assembly errors and both rotation angles, the angles' sine, cosine and tangent
#: packed once (Layout trig): the loaded TCA's gap Newton evaluates Eq 38's position rows at many points of one
#: state, and the eight sines and cosines were a third of each evaluation (ltca; docs/performance.md)
MESH_STATE = Layout("MeshState", "The assembly errors of Eq 34 and both rotation angles of one mesh state.", (
    *ERRORS.fields,
    Field("pinion_angle_rad", phi1p, "rad", "pinion rotation phi'_1 of Eq 30"),
    Field("gear_angle_rad", phi2p, "rad", "gear rotation phi'_2 of Eq 34"),
), trig=("vertical_rad", "horizontal_rad", "pinion_angle_rad", "gear_angle_rad"))


def _camel(name):
    return "".join(w.capitalize() for w in name.split("_"))


def surface_layout(model_name, model):
    extra = tuple(getattr(model, "PARAMETERS", ()))
    return Layout(f"{_camel(model_name)}SurfaceParams",
                  f"Parameters of the '{model_name}' tooth-surface model ({model.__name__.rsplit('.', 1)[-1]}.py).",
                  RACK_FIELDS + extra, trig=RACK_ANGLES)


_LU = [Arg("l", l, "mm", "profile parameter along the rack edge"), Arg("u", u, "mm", "parameter along the tooth")]


def fundamental_forms(jac, hess, normal):
    """First and second fundamental forms (2x2 Matrices) of a surface from its [R_l, R_u] (3x2),
    [R_ll, R_lu, R_uu] (3x3) and unit normal; the second form is taken about that normal."""
    ru, rv = jac[:, 0], jac[:, 1]
    first = sp.Matrix([[ru.dot(ru), ru.dot(rv)], [ru.dot(rv), rv.dot(rv)]])
    L, M, N = (hess[:, k].dot(normal) for k in range(3))
    return first, sp.Matrix([[L, M], [M, N]])


def surface_function(model):
    """The name of the function a model's surface is derived from: ``tooth_surface_staged`` (written
    over named intermediate values, the base jets), else ``tooth_surface_late`` (abstract forms
    differentiated, substituted after), else ``tooth_surface``."""
    return next(f for f in ("tooth_surface_staged", "tooth_surface_late", "tooth_surface") if hasattr(model, f))


def surface_module(model_name, model):
    lay = surface_layout(model_name, model)
    params = Arg("params", lay, "", "surface parameters")
    fns = []
    function = surface_function(model)
    for name, sigma in FLANKS:
        stages = ()
        if function == "tooth_surface_staged":
            p, n, ph, late, stages = model.tooth_surface_staged(sigma)
        elif function == "tooth_surface_late":
            p, n, ph, late = model.tooth_surface_late(sigma)
        else:
            (p, n, ph), late = model.tooth_surface(sigma), None
        jac = p.jacobian([l, u])
        njac = n.jacobian([l, u])
        hess = sp.Matrix([[p[i].diff(l, 2), p[i].diff(l, u), p[i].diff(u, 2)] for i in range(3)])
        if late is not None:
            p, n, ph, jac, njac, hess = (late(e) for e in (p, n, ph, jac, njac, hess))
        fns.append(Function(
            f"surface_{name}", f"Tooth surface of the {name} flank in the member frame S_i.", _LU + [params],
            [Output("point", p, "mm", "surface point [x, y, z]"),
             Output("normal", n, "1", "unit normal, outward from the tooth"),
             Output("roll_angle", ph, "rad", "generating roll angle phi(l, u) of Eq 7")], stages))
        fns.append(Function(
            f"surface_jet_{name}", f"Point, unit normal and their first derivatives, {name} flank.", _LU + [params],
            [Output("point", p, "mm", "surface point [x, y, z]"),
             Output("normal", n, "1", "unit normal, outward from the tooth"),
             Output("point_D_lu", jac, "mm/mm", "[dR/dl, dR/du] as columns"),
             Output("normal_D_lu", njac, "1/mm", "[dn/dl, dn/du] as columns")], stages))
        fns.append(Function(
            f"surface_second_derivatives_{name}", f"Second derivatives of the {name} flank point in (l, u).",
            _LU + [params],
            [Output("point_D2_lu", hess, "mm/mm^2", "[d2R/dl2, d2R/dldu, d2R/du2] as columns")], stages))
        first, second = fundamental_forms(jac, hess, n)
        fns.append(Function(
            f"surface_fundamental_forms_{name}",
            f"First and second fundamental forms of the {name} flank in (l, u) (curvature; beveloid/curvature.py).",
            _LU + [params],
            [Output("point_D_lu", jac, "mm/mm", "[dR/dl, dR/du] as columns"),
             Output("normal", n, "1", "unit normal, outward from the tooth"),
             Output("first_form", first, "mm^2", "[[E, F], [F, G]]: E = R_l.R_l, F = R_l.R_u, G = R_u.R_u"),
             Output("second_form", second, "mm",
                    "[[L, M], [M, N]] about the outward normal n: L = R_ll.n, M = R_lu.n, N = R_uu.n "
                    "(negative on a convex tooth)")], stages))
    source = model.__name__.rsplit(".", 1)[-1] + ".py"
    return ModuleSpec(f"surface_{model_name}", source,
                      f"Tooth surfaces of the '{model_name}' model and their derivatives in (l, u).", fns,
                      scalar_twin=True)


def _vec(prefix, n):
    return sp.Matrix(sp.symbols(f"{prefix}_0:{n}", real=True))


def _mat(prefix, rows, cols):
    return sp.Matrix(rows, cols, sp.symbols(f"{prefix}_0:{rows * cols}", real=True))


def _placement_subs():
    return {d_w1 - b_c1: _z1, d_w2 - b_c2: _z2}


def _placed(expr):
    e = sp.Matrix(expr).subs(_placement_subs())
    return e.subs({d_w1: _z1 + b_c1, d_w2: _z2 + b_c2})


def placement_module():
    mm = eq28_38_meshing_model
    errs = Arg("errors", ERRORS, "", "assembly errors")
    pair = Arg("pair", PLACEMENT, "", "pair placement")
    t1 = _placed(mm.M_f1[:3, 3])
    t2 = _placed(mm.M_f2[:3, 3])
    return ModuleSpec("placement", "eq28_38_meshing_model.py",
                      "Placement of the pinion and the gear in the fixed frame S_f (Eqs 30-35).", [
        Function("pinion_placement", "Pinion frame S_1 in S_f at pinion angle phi'_1 (Eqs 30-31).",
                 [Arg("pinion_angle", phi1p, "rad", "phi'_1 of Eq 30"), pair],
                 [Output("rotation", mm.L_f1, "1", "L_f1"), Output("translation", t1, "mm", "origin of S_1 in S_f")]),
        Function("gear_placement", "Gear frame S_2 in S_f at gear angle phi'_2 with the errors (Eqs 32-35).",
                 [Arg("gear_angle", phi2p, "rad", "phi'_2 of Eq 34"), errs, pair],
                 [Output("rotation", _placed(mm.L_f2), "1", "L_f2"),
                  Output("translation", t2, "mm", "origin of S_2 in S_f")]),
    ])


def contact_system_module():
    """Eq 38 over abstract surface jets: any pair of surface models plugs in."""
    mm = eq28_38_meshing_model
    p1, n1, p2, n2 = _vec("pinion_point", 3), _vec("pinion_normal", 3), _vec("gear_point", 3), _vec("gear_normal", 3)
    dp1, dn1 = _mat("pinion_point_D_lu", 3, 2), _mat("pinion_normal_D_lu", 3, 2)
    dp2, dn2 = _mat("gear_point_D_lu", 3, 2), _mat("gear_normal_D_lu", 3, 2)
    f = _placed(mm.tca_residual(p1, n1, p2, n2))
    F1 = f.jacobian(list(p1)) * dp1 + f.jacobian(list(n1)) * dn1
    F2 = f.jacobian(list(p2)) * dp2 + f.jacobian(list(n2)) * dn2
    d_unknowns = F1.row_join(F2).row_join(f.diff(phi2p))
    errors = ERRORS.symbols()
    args = [Arg("pinion_point", p1, "mm", "pinion flank point in S_1"),
            Arg("pinion_normal", n1, "1", "pinion unit outward normal in S_1"),
            Arg("pinion_point_D_lu", dp1, "mm/mm", "pinion [dR/dl, dR/du]"),
            Arg("pinion_normal_D_lu", dn1, "1/mm", "pinion [dn/dl, dn/du]"),
            Arg("gear_point", p2, "mm", "gear flank point in S_2"),
            Arg("gear_normal", n2, "1", "gear unit outward normal in S_2"),
            Arg("gear_point_D_lu", dp2, "mm/mm", "gear [dR/dl, dR/du]"),
            Arg("gear_normal_D_lu", dn2, "1/mm", "gear [dn/dl, dn/du]"),
            Arg("pinion_angle", phi1p, "rad", "phi'_1 of Eq 30"),
            Arg("gear_angle", phi2p, "rad", "phi'_2 of Eq 34"),
            Arg("errors", ERRORS, "", "assembly errors"),
            Arg("pair", PLACEMENT, "", "pair placement")]
    return ModuleSpec("contact_system", "eq28_38_meshing_model.py",
                      "The TCA system of Eq 38 from two surface jets, with exact Jacobians.", [
        Function("contact_residual", "Eq 38 and its Jacobians for surface points given with their first derivatives.",
                 args,
                 [Output("residual", f, "mm | 1", "[R_f1 - R_f2 (x, y, z), (n_f1 + n_f2)_x, (n_f1 + n_f2)_z]"),
                  Output("residual_D_unknowns", d_unknowns, "", "d residual / d " + str(UNKNOWNS)),
                  Output("residual_D_errors", f.jacobian(errors), "", "d residual / d AssemblyErrors"),
                  Output("residual_D_pinion_angle", f.diff(phi1p), "", "d residual / d phi'_1")]),
        Function("position_residual",
                 "The position rows of Eq 38 (R_f1 - R_f2) and their Jacobians at one mesh state, its angles' "
                 "trigonometry packed (the loaded TCA's gap Newton reads only these).",
                 [args[0], args[2], args[4], args[6], Arg("state", MESH_STATE, "", "the mesh state"), args[11]],
                 [Output("residual", f[:3, :], "mm", "R_f1 - R_f2 (x, y, z): rows 0-2 of contact_residual's"),
                  Output("residual_D_unknowns", d_unknowns[:3, :], "", "d residual / d " + str(UNKNOWNS)),
                  Output("residual_D_pinion_angle", f[:3, :].diff(phi1p), "", "d residual / d phi'_1")]),
    ], scalar_twin=True, constants={"UNKNOWNS": UNKNOWNS}, extra_layouts=(CONTACT_UNKNOWNS,))


def flank_boundaries_module():
    fb = flank_boundaries
    m = fb.margins()
    args = [Arg("point", fb.POINT, "mm", "flank point in the member frame S_i"),
            Arg("l", l, "mm", "the point's rack parameter l"),
            Arg("blank", fb.BLANK, "", "the member's blank")]
    return ModuleSpec("flank_boundaries", "flank_boundaries.py",
                      "Signed margins (mm, positive inside) of a flank point to the blank's boundaries.", [
        Function("flank_margins", "Margins to the form limit, tip, toe and heel, and their derivatives.", args,
                 [Output("margins", m, "mm", "[form limit, tip, toe, heel]"),
                  Output("margins_D_point", m.jacobian(list(fb.POINT)), "mm/mm", "d margins / d point"),
                  Output("margins_D_l", m.diff(l), "mm/mm", "d margins / d l")]),
    ], scalar_twin=True, constants={"BOUNDARIES": fb.BOUNDARIES})


def edge_contact_module():
    """Boundary jets and the edge tangency rows over abstract surface jets (derivations/edge_contact.py)."""
    ec = edge_contact
    p, dp, d2p = ec.surface_jet_symbols("flank")
    m, m1, m2 = ec.boundary_jet(p, dp, d2p)
    jet_args = [Arg("point", p, "mm", "flank point in the member frame S_i"),
                Arg("point_D_lu", dp, "mm/mm", "[dR/dl, dR/du]"),
                Arg("point_D2_lu", d2p, "mm/mm^2", "[d2R/dl2, d2R/dldu, d2R/du2]"),
                Arg("l", l, "mm", "the point's rack parameter l"),
                Arg("blank", flank_boundaries.BLANK, "", "the member's blank")]
    fns = [Function("boundary_jet", "Margins of a flank point to its blank and their derivatives in (l, u).",
                    jet_args,
                    [Output("margins", m, "mm", "[form limit, tip, toe, heel], positive inside"),
                     Output("margins_D_lu", m1, "mm/mm", "d margins / d(l, u)"),
                     Output("margins_D2_lu", m2, "mm/mm^2", "[d2/dl2, d2/dldu, d2/du2] of the margins")])]
    errors, pair = Arg("errors", ERRORS, "", "assembly errors"), Arg("pair", PLACEMENT, "", "pair placement")
    for member in ("pinion", "gear"):
        other = "gear" if member == "pinion" else "pinion"
        row, d_unknowns, d_errors, d_phi1, (cdp, cd2p, g1, g2, n, dn) = ec.edge_tangency(member)
        fns.append(Function(
            f"{member}_edge_tangency",
            f"Edge contact: a {member} boundary curve g = 0 tangent to the {other} flank, (L t) . n_f = 0.",
            [Arg(f"{member}_point_D_lu", cdp, "mm/mm", f"{member} [dR/dl, dR/du]"),
             Arg(f"{member}_point_D2_lu", cd2p, "mm/mm^2", f"{member} [d2R/dl2, d2R/dldu, d2R/du2]"),
             Arg("g_D_lu", g1, "mm/mm", "d g / d(l, u) of the boundary"),
             Arg("g_D2_lu", g2, "mm/mm^2", "[g_ll, g_lu, g_uu] of the boundary"),
             Arg(f"{other}_normal", n, "1", f"{other} unit outward normal in S_i"),
             Arg(f"{other}_normal_D_lu", dn, "1/mm", f"{other} [dn/dl, dn/du]"),
             Arg("pinion_angle", phi1p, "rad", "phi'_1 of Eq 30"),
             Arg("gear_angle", phi2p, "rad", "phi'_2 of Eq 34"), errors, pair],
            [Output("tangency", _placed(sp.Matrix([row]))[0, 0], "mm/mm",
                    "(L t) . n_f of the other member, t = R_l g_u - R_u g_l"),
             Output("tangency_D_unknowns", _placed(d_unknowns), "", "d tangency / d " + str(UNKNOWNS)),
             Output("tangency_D_errors", _placed(d_errors), "", "d tangency / d AssemblyErrors"),
             Output("tangency_D_pinion_angle", _placed(sp.Matrix([d_phi1]))[0, 0], "", "d tangency / d phi'_1")]))
    return ModuleSpec("edge_contact", "edge_contact.py",
                      "Edge and corner contact over abstract surface jets: boundary jets and tangency rows.", fns,
                      scalar_twin=True)


FILLET = Layout("FilletParams", "Parameters of the root fillet (root_fillet.py): the rack, its tip round and crowning.",
                RACK_FIELDS + root_fillet.PARAMETERS, trig=RACK_ANGLES)
_PSI_U = [Arg("psi", root_fillet.psi, "rad", "fillet profile parameter: 0 at the root, junction_psi at the flank"),
          Arg("u", u, "mm", "parameter along the tooth")]


def fillet_module():
    """The root fillet (envelope of the rack's tip round) per flank, and the round's constants."""
    rf = root_fillet
    params = Arg("params", FILLET, "", "fillet parameters")
    fns = [Function("tip_round", "The rack's tip round: where it meets the straight edge, and the largest that fits.",
                    [params],
                    [Output("junction_l", rf.junction_l(), "mm", "l_t: the straight edge (flank) starts there"),
                     Output("junction_psi", rf.junction_psi(), "rad", "psi_J: the fillet meets the flank there"),
                     Output("max_radius", rf.max_radius(), "mm", "largest rho_a0 that fits the rack tooth")])]
    for name, sigma in FLANKS:
        p, n, ph = rf.fillet_surface(sigma)
        fns.append(Function(f"fillet_{name}", f"Root fillet of the {name} flank in the member frame S_i.",
                            _PSI_U + [params],
                            [Output("point", p, "mm", "fillet point [x, y, z]"),
                             Output("normal", n, "1", "unit normal, outward from the tooth"),
                             Output("roll_angle", ph, "rad", "generating roll angle phi(psi, u) of Eq 7")]))
        fns.append(Function(f"fillet_jet_{name}", f"Fillet point, unit normal and their first derivatives, {name} flank.",
                            _PSI_U + [params],
                            [Output("point", p, "mm", "fillet point [x, y, z]"),
                             Output("normal", n, "1", "unit normal, outward from the tooth"),
                             Output("point_D_pu", p.jacobian([rf.psi, u]), "mm/(rad, mm)", "[dR/dpsi, dR/du] as columns"),
                             Output("normal_D_pu", n.jacobian([rf.psi, u]), "1/(rad, mm)",
                                    "[dn/dpsi, dn/du] as columns")]))
    return ModuleSpec("root_fillet", "root_fillet.py",
                      "Root fillet: envelope of the rack's tip round (Eq 7), per flank, in (psi, u).", fns)


SECTION = Layout("ToothSectionParams", "A member's rack and tip for its transverse sections (tooth_sections.py).",
                 RACK_FIELDS + tooth_sections.PARAMETERS, trig=RACK_ANGLES)


def tooth_sections_module():
    """Transverse sections: tip and root cones, involute data, undercut and thickness per section z."""
    ts = tooth_sections
    zarg = Arg("z", ts.z, "mm", "the section's axial position in the member frame S_i")
    params = Arg("params", SECTION, "", "the member's rack and tip")
    r_tip = ts.tip_radius()
    theta_tip = ts.thickness_angle(r_tip)
    outs = [Output("tip_radius", r_tip, "mm", "tip-cone radius"),
            Output("root_radius", ts.root_radius(), "mm", "root-cone radius (the rack's tip line)"),
            Output("tip_thickness_angle", theta_tip, "rad", "angular tooth thickness at the tip-cone radius"),
            Output("tip_arc_thickness", r_tip * theta_tip, "mm",
                   "arc tooth thickness at the tip-cone radius (negative: the flanks cross below it)")]
    for name, sigma in ts.FLANK_SIGNS:
        outs += [Output(f"pressure_angle_{name}", ts.pressure_angle(sigma), "rad", f"transverse pressure angle, {name}"),
                 Output(f"base_radius_{name}", ts.base_radius(sigma), "mm", f"base radius, {name}"),
                 Output(f"undercut_depth_{name}", ts.undercut_depth(sigma), "mm",
                        f"rack form point below the interference point T, {name} (> 0: undercut)"),
                 Output(f"form_radius_{name}", ts.form_radius(sigma), "mm",
                        f"start of the involute, {name} (valid where undercut_depth <= 0)")]
    theta = ts.thickness_angle()
    return ModuleSpec("tooth_sections", "tooth_sections.py",
                      "Transverse sections of a member's tooth: cones, involutes, undercut and thickness.", [
        Function("transverse_section", "The section z: tip and root cones, involute data per flank, tip thickness.",
                 [zarg, params], outs),
        Function("thickness_at_radius", "Angular and arc tooth thickness at a radius of the section z.",
                 [zarg, Arg("radius", ts.R, "mm", "radius in the section"), params],
                 [Output("thickness_angle", theta, "rad", "angular tooth thickness"),
                  Output("arc_thickness", ts.R * theta, "mm", "arc tooth thickness"),
                  Output("thickness_angle_D_radius", theta.diff(ts.R), "rad/mm", "d thickness_angle / d radius")]),
    ])


def tooth_plate_coupling_module():
    """The cantilever plate strip's edge compliance per face mode (tooth_plate_coupling.py)."""
    pc = tooth_plate_coupling
    args = [Arg("t", pc.t, "1", "k h: wave number along the face times the plate (tooth) height"),
            Arg("nu", pc.nu, "1", "Poisson's ratio")]
    return ModuleSpec("tooth_plate_coupling", "tooth_plate_coupling.py",
                      "Face coupling of the tooth beams: a Kirchhoff cantilever plate strip's edge compliance per mode.", [
        Function("edge_compliance_ratio", "R(t) = C(k) / C(0), the closed form (exp(-2t); for t >= 0.03: below, "
                 "where it cancels, edge_compliance_ratio_series).", args,
                 [Output("ratio", pc.edge_compliance_ratio(), "1", "edge compliance of mode k over the beam's")]),
        Function("edge_compliance_ratio_series", "R(t) to O(t^8), for t < 0.03 (relative error below 1e-13 there; the closed form 1e-12 at 0.03).", args,
                 [Output("ratio", pc.edge_compliance_ratio_series(), "1",
                         "edge compliance of mode k over the beam's")]),
    ])


def patch_clearance_module():
    """The rigid map S_1 -> S_2 at phi'_2 = 0 of the patch-clearance pre-check (patch_clearance.py)."""
    pc = patch_clearance
    return ModuleSpec("patch_clearance", "patch_clearance.py",
                      "Whether a pinion flank patch can reach the gear blank at a pinion angle, at any gear angle.", [
        Function("pinion_in_gear_frame",
                 "The pinion frame S_1 seen from the gear frame S_2 at phi'_2 = 0: M_21 = M_f2(0)^-1 M_f1(phi'_1).",
                 [Arg("pinion_angle", phi1p, "rad", "phi'_1 of Eq 30"), Arg("errors", ERRORS, "", "assembly errors"),
                  Arg("pair", PLACEMENT, "", "pair placement")],
                 [Output("rotation", _placed(pc.L_21), "1", "L_21: pinion axes in S_2"),
                  Output("translation", _placed(pc.T_21), "mm", "origin of S_1 in S_2")]),
    ], scalar_twin=True)


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


#: One member's design outputs as a record: field -> the kernels' output name without its member
#: number (1 pinion, 2 gear).  The generator emits the record (layouts.MemberDesignOutputs) and, per
#: member, which output fills each field (design_equations.MEMBER_OUTPUTS): the runtime reads names.
_MEMBER_RECORD = (
    ("helix_angle", "beta", "rad", "helix angle"), ("cone_angle", "gamma", "rad", "cone angle"),
    ("transverse_angular_factor", "xi_t", "1", "transverse angular factor (Eq 22-23)"),
    ("mounting_distance_mm", "d", "mm", "mounting distance (Eqs 13-14)"),
    ("working_mounting_distance_mm", "d_w", "mm", "working mounting distance"),
    ("working_cone_angle", "gamma_w", "rad", "working cone angle"),
    ("working_helix_angle", "beta_w", "rad", "working helix angle"),
    ("working_pitch_radius_mm", "r_w", "mm", "working pitch radius"),
    ("reference_pitch_radius_mm", "r", "mm", "reference pitch radius"),
    ("transverse_pressure_angle_left", "alpha_PL", "rad", "transverse pressure angle, left, reference"),
    ("transverse_pressure_angle_right", "alpha_PR", "rad", "transverse pressure angle, right, reference"),
    ("working_transverse_pressure_angle_left", "alpha_PwL", "rad", "transverse pressure angle, left, working"),
    ("working_transverse_pressure_angle_right", "alpha_PwR", "rad", "transverse pressure angle, right, working"),
    ("fpd_angle_left", "xi_L", "rad", "FPD angle, left (Eq 19)"),
    ("fpd_angle_right", "xi_R", "rad", "FPD angle, right (Eq 20)"),
    ("cos_pitch_point_angle", "cos_theta", "1", "cos of the pitch point angle on the cone"),
    ("sin_pitch_point_angle", "sin_theta", "1", "sin of the pitch point angle on the cone"),
)
MEMBER_DESIGN = Layout("MemberDesignOutputs", "One member's outputs of the direct or indirect design, by name.",
                       tuple(Field(f, sp.Symbol(f, real=True), unit, doc) for f, _, unit, doc in _MEMBER_RECORD))


def member_output_names():
    """{"pinion": {field: output name}, "gear": {...}}, every name an output of the design kernels."""
    outputs = {k for k, _, _ in _DESIGN_OUTPUTS}
    out = {member: {f: f"{stem}{number}" for f, stem, _, _ in _MEMBER_RECORD}
           for member, number in (("pinion", 1), ("gear", 2))}
    missing = {n for names in out.values() for n in names.values()} - outputs
    assert not missing, f"member record names outputs the design kernels lack: {sorted(missing)}"
    return out


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
    ], constants={"MEMBER_OUTPUTS": member_output_names()}, extra_layouts=(MEMBER_DESIGN,))


def glue_context(models=None):
    """The context the glue templates render from: plain data (names, counts, keys), so that the
    runtime can compose the glue of built-in and user models without sympy (beveloid/models/)."""
    models = models or SURFACE_MODELS
    ctx = dict(models=[model_entry(k, m) for k, m in models.items()])
    ctx.update(glue_base())
    return ctx


def glue_base():
    """The model-independent part of the glue context (flanks, unknowns, errors, boundaries)."""
    return dict(flanks=[f for f, _ in FLANKS], unknowns=list(UNKNOWNS), n_errors=len(ERRORS.fields),
                boundaries=list(flank_boundaries.BOUNDARIES),
                opposite=[flank_boundaries.BOUNDARIES.index(flank_boundaries.OPPOSITE[b])
                          for b in flank_boundaries.BOUNDARIES])


def model_entry(name, model):
    """One model's entry of the glue context: its modules, layout, parameter count and input keys."""
    lay = surface_layout(name, model)
    fields = {f.name: f for f in getattr(model, "PARAMETERS", ())}
    return dict(name=name, module=f"surface_{name}", layout=lay.name, nparams=len(lay.fields),
                input_keys=[dict(name=k, unit=fields[k].unit, doc=fields[k].doc, default=float(d), lo=float(lo),
                                 hi=float(hi)) for k, (d, lo, hi) in getattr(model, "KEYS", {}).items()],
                selected_by=list(getattr(model, "SELECTED_BY", ())),
                choice_keys=[dict(name=k, doc=fields[k].doc, default=d,
                                  choices=[dict(name=c, value=float(v)) for c, v in ch.items()])
                             for k, (d, ch) in getattr(model, "CHOICE_KEYS", {}).items()])


#: the glue modules and their templates
GLUE_TEMPLATES = {"tca_kernels.py": "tca_kernels.py.jinja", "tca_kernels_scalar.py": "tca_kernels_scalar.py.jinja",
                  "surface_models.py": "surface_models.py.jinja"}


def glue_files(models=None):
    """The generated glue: model dispatch and the composed contact system, numpy and scalar."""
    ctx = glue_context(models)
    return {name: codegen.render_template(tpl, **ctx) for name, tpl in GLUE_TEMPLATES.items()}


def module_specs(models=None):
    models = models or SURFACE_MODELS
    return ([surface_module(k, m) for k, m in models.items()]
            + [placement_module(), contact_system_module(), flank_boundaries_module(), edge_contact_module(),
               patch_clearance_module(), design_module(), fillet_module(),
               tooth_sections_module(), tooth_plate_coupling_module(), contact_kinematics_module()])


def composed_residual(pinion_model="involute", gear_model="involute", flank="right"):
    """Eq 38 with both members' surfaces substituted, symbolic (for baselines and checks).

    Returns (residual Matrix(5), unknowns [l1, u1, l2, u2, phi'_2], phi'_1, error symbols,
    pinion parameter symbols, gear parameter symbols, placement symbols); the parameter
    symbols follow the fields of each model's layout and of PairPlacement.
    """
    sigma = dict(FLANKS)[flank]
    unknowns = list(sp.symbols("l_1 u_1 l_2 u_2", real=True)) + [phi2p]

    def member(model_name, tag, l_sym, u_sym):
        model = SURFACE_MODELS[model_name]
        lay = surface_layout(model_name, model)
        fresh = {f.symbol: sp.Symbol(f"{tag}_{f.name}", real=True) for f in lay.fields}
        p, n, _ = model.tooth_surface(sigma)
        sub = {**fresh, l: l_sym, u: u_sym}
        return p.xreplace(sub), n.xreplace(sub), [fresh[f.symbol] for f in lay.fields]

    p1, n1, s1 = member(pinion_model, "pinion", unknowns[0], unknowns[1])
    p2, n2, s2 = member(gear_model, "gear", unknowns[2], unknowns[3])
    f = _placed(eq28_38_meshing_model.tca_residual(p1, n1, p2, n2))
    return f, unknowns, phi1p, ERRORS.symbols(), s1, s2, PLACEMENT.symbols()


def contact_kinematics_module():
    """The surface velocities at a contact point (contact_kinematics.py): sliding and sum velocity."""
    from . import contact_kinematics as ck

    v = ck.velocities()
    args = [Arg("pinion_point", ck.POINT, "mm", "the contact point on the pinion flank, in S_1"),
            Arg("pinion_normal", ck.NORMAL, "1", "the pinion's unit outward normal there, in S_1"),
            Arg("pinion_angle", phi1p, "rad", "phi'_1 of Eq 30"),
            Arg("pinion_speed", ck.omega1, "rad/s", "the pinion's angular speed dphi'_1/dt"),
            Arg("pinion_teeth", N1, "1", "pinion tooth number N1"), Arg("gear_teeth", N2, "1", "gear tooth number N2"),
            Arg("errors", ERRORS, "", "assembly errors"), Arg("pair", PLACEMENT, "", "pair placement")]
    outs = [Output("point", _placed(v["point"]), "mm", "the contact point in S_f"),
            Output("normal", _placed(v["normal"]), "1", "the pinion's outward normal in S_f"),
            Output("pinion_velocity", _placed(v["pinion_velocity"]), "m/s", "pinion surface velocity, tangent part, S_f"),
            Output("gear_velocity", _placed(v["gear_velocity"]), "m/s", "gear surface velocity, tangent part, S_f"),
            Output("sliding_velocity", _placed(v["sliding_velocity"]), "m/s", "pinion minus gear, tangent plane, S_f"),
            Output("sum_velocity", _placed(v["sum_velocity"]), "m/s", "pinion plus gear, tangent plane, S_f"),
            Output("approach_speed", _placed(sp.Matrix([v["approach_speed"]]))[0], "m/s",
                   "(V_1 - V_2).n: zero at a point of rigid conjugate contact")]
    return ModuleSpec("contact_kinematics", "contact_kinematics.py",
                      "Surface velocities at a contact point of the assembled pair: sliding and sum velocity.", [
        Function("contact_velocities", "The members' surface velocities at a pinion flank point, in the fixed "
                 "frame, and their sliding and sum velocities in the tangent plane.", args, outs)])

"""Pitch-cone design of a crossed beveloid gear pair (Section 3.4 and Fig. 7 of the paper).

Two procedures, both built on the generated kernels of
``beveloid.generated.design_equations`` (the only place the paper's Eqs 12-27 are
evaluated at run time; this module never imports sympy):

``design(spec) -> DesignResult`` -- the *direct* design (first chart of Fig. 7).
    Inputs (from a :class:`beveloid.spec.DesignSpec`): m_n, alpha_n, delta, E
    (``[pair]``), N1, gamma1, beta1, x_t1 (``[pinion]``), N2, gamma2 (``[gear]``) and the
    blank data (face widths, addendum coefficients, b_c).  The working normal pressure
    angle alpha_nw is the root of ``offset_residual(alpha_nw, ...) = E(alpha_nw) - E``
    (Eq 17 with the working data of Eqs 16, 23, 25, 26), found by a safeguarded
    Newton/bisection iteration with the exact derivative ``residual_D_alpha_nw`` to
    ``|residual| < 1e-11 mm`` (relaxed to 8 ulp of E for E > ~5600 mm; where E(alpha_nw) is so steep
    -- next to the end of the tangency range, E -> 0 -- that alpha_nw reaches floating-point
    resolution first, the attained residual is accepted and a note says so).  The admissible
    interval of alpha_nw is where the kernel is real: ``sin(alpha_nw) > |sin(gamma_i)| sin(alpha_n)``
    (Eq 25), the Eq 26 arcsine and the Eq 16 arccosine (pitch-cone tangency) defined, and
    ``alpha_nw < 60 deg``; it is scanned on a grid for sign changes.  If Eq 17 has several roots
    the one closest to alpha_n is taken and a note says so.  ``direct_design(alpha_nw, ...)``
    then gives every other quantity: gear helix angle beta2 (Eq 26), gear profile shift x_t2
    (Eq 27, backlash free), transverse angular factors (Eqs 22-23), working cone and helix
    angles (Eqs 25, 26, 16), mounting distances (Eqs 13-14), FPD angles (Eqs 18-20).

``indirect_design(spec_like, alpha_nw, pinion_working_cone_angle, gear_working_cone_angle,
pinion_working_helix_angle) -> DesignResult`` -- the *indirect* design (second chart of Fig. 7).
    Inputs: the working data alpha_nw, gamma_w1, gamma_w2, beta_w1 (radians) and, from
    ``spec_like``, m_n, alpha_n, delta, N1, N2, x_t1 and the blank data.  The reference data
    gamma1, gamma2 (Eq 25), beta1, beta2 (Eq 26), beta_w2 (Eq 16), E (Eq 17) and x_t2 (Eq 27)
    are computed; ``spec_like``'s values of ``pair.offset_mm``, ``pinion.cone_angle_deg``,
    ``pinion.helix_angle_deg`` and ``gear.cone_angle_deg`` are ignored (they are outputs) and
    may be omitted when ``spec_like`` is a dict.  ``result.spec`` holds the computed reference
    data, so ``design(result.spec)`` repeats the design the direct way.

Units: lengths in mm, angles in radians everywhere in this module (degrees only in
``beveloid.design.report`` and in messages).  Helix angles are signed (+ right hand).

Feasibility problems raise :class:`DesignError` (a :class:`beveloid.errors.UserError`) with a
one-line message naming the key(s), the value(s), what fails and which way to move, e.g.::

    pair.offset_mm = 10.0: no working normal pressure angle solves Eq 17: the offset is too
    small for the given teeth, module and helix angles (...); increase pair.offset_mm ...

Checks besides the paper's equations (plain numpy geometry in the reference transverse
section, tip radius ``r + x_t m_t + h_a m_n / cos(gamma)``):

* pointed teeth -- transverse tooth thickness at the tip ``<= 0.2 m_n``: an error;
* undercut -- the cutter tip line ``(a - s)/cos(gamma)`` below the pitch circle lies beyond the
  interference point ``r sin^2(alpha_P)`` of a flank (a = cutter addendum, s = rack shift):
  a warning in ``result.notes``;
* a transverse pressure angle (reference or working, either flank, either member) ``<= 0``,
  from the tilted rack ``tan(alpha_P) = (tan(alpha_n) cos(gamma) +- sin(beta) sin(gamma)) / cos(beta)``:
  an error (the flank leans past the radial direction; the generated ``alpha_Pw = arccos(xi_t cos(alpha_P))``
  and hence Eq 27 assume ``alpha_P > 0``);
* the pitch point P off the active profile -- in the working-pitch-circle section (z = b_c) the
  working pitch radius must lie between the form circle (where the rack's straight edge starts) and the
  tip circle, for both members and both flanks (:func:`pitch_point_margins`): an error, since the
  design's defining contact at P would not be on the teeth (e.g. alpha_nw = 4.2 deg with a 1 mm offset
  on case 1).  A negative mounting distance d alone is not rejected: with signed cone angles the apex
  may lie on either side of the crossing point;
* a zero cone angle (the cone apex, hence the mounting distance, is at infinity), a gear helix
  angle ``|beta2| >= 80 deg`` and non-finite or non-positive results: errors.

One implementation for one design and for many: ``design_arrays(values)`` (``arrays``) designs n
designs given by spec values (dotted key -> (n,) arrays) and names each one's outcome
(:class:`Outcome`: ``ok`` or the first check it fails); ``design(spec)`` is it at n = 1 plus the
refusal that explains the outcome; ``beveloid explore`` calls it on chunks of designs.

Modules: ``kernels`` (the generated kernels, by name), ``solve`` (alpha_nw, over arrays), ``arrays``
(the design of n designs), ``direct`` (design), ``indirect`` (indirect_design), ``members`` (the result
types, DesignError), ``checks`` (the checks above, their outcomes and the tooth/pitch-point refusals),
``refusals`` (the other one-line refusals), ``report`` (Table 1 text and JSON).
"""
from __future__ import annotations

from .arrays import ArrayDesign, design_arrays, spec_values
from .checks import MAX_GEAR_HELIX_ANGLE, POINTED_TIP_FACTOR, Outcome, pitch_point_margins
from .direct import design
from .indirect import indirect_design
from .members import RAD, DesignError, DesignResult, MemberDesign
from .report import TABLE1_ROWS, design_json, format_table1
from .solve import MAX_WORKING_PRESSURE_ANGLE, RESIDUAL_TOLERANCE_MM

__all__ = [
    "ArrayDesign",
    "design_arrays",
    "spec_values",
    "Outcome",
    "DesignError",
    "MemberDesign",
    "DesignResult",
    "design",
    "indirect_design",
    "pitch_point_margins",
    "format_table1",
    "design_json",
    "TABLE1_ROWS",
    "RAD",
    "MAX_WORKING_PRESSURE_ANGLE",
    "MAX_GEAR_HELIX_ANGLE",
    "POINTED_TIP_FACTOR",
    "RESIDUAL_TOLERANCE_MM",
]

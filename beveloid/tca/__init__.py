"""Tooth contact analysis (package) of crossed beveloid gears under the five assembly errors (Eqs 28-38).

Built on the generated kernels only: each member's tooth-surface model (``surface_<model>``),
the Eq 38 contact system composed from them (``tca_kernels``) and the flank margins.  The
contact solver itself is :mod:`beveloid.solver` (one core, a numpy and a compiled backend).

Conventions (the paper is silent on these; see docs/validation.md):

* Flanks are named after the signs of Eqs 1-3 (upper sign = left).  The left flank of the
  pinion meshes with the left flank of the gear (both are the same flank plane of the common
  rack, Eq 18).
* Normals are outward from each tooth, so the contact condition is n_f1 = -n_f2.
* Each member's frame S_i has its origin on the axis in the reference transverse section
  (where its profile shift equals x_t).  That section lies b_c (``reference_section_offset_mm``)
  below the working pitch circle, which passes through the pitch point P of the pitch-cone
  design; default b_c = 0.  Face widths are centred on the working pitch circle.
* Flank boundaries (derivations/flank_boundaries.py): face width (toe and heel at -+W/2 about
  the working pitch circle), tip cone (tip height ``addendum_coefficient * m_n`` above the rack
  pitch plane, parallel to the root cone), form limit l >= 0 (the start of the rack's straight
  edge; no fillet).
* Pair k (k = ..., -1, 0, 1, ...) is pinion tooth k with gear tooth k.  Because each pair's
  solution is pair 0's solution turned by whole tooth pitches, pair 0 is solved on the
  shifted pinion angles and the points are turned back into place.
* TE = phi'_2 - phi'_2,ref + (N1/N2)(phi'_1 - phi'_1,ref), the reference being the contact
  at the pitch point P of the aligned pair on the same flank.

Shape (as every analysis package): :class:`Options` (frozen, self-validating: the one range
table the CLI reads; the errors too), ``analyze(pair_or_geometry, options, *, solver=None) ->
TCAResult`` (a :class:`beveloid.result.Result`: deep-frozen, holding its pair and options, with its contact
ellipses at ``options.approach_mm``), its JSON by ``TCAResult.to_json()``.  Modules: contact (kernels and unknowns by name), reference (the
pitch-point contact, first-touch sign), grid (the solver over error sets x angles), flank (one
flank over the mesh), backlash, sensitivity, result; the TE formula and the pair envelope are
:mod:`beveloid.mesh`.
"""
from __future__ import annotations

from ..geometry import Member, PairGeometry  # noqa: F401  (re-exported: tca.PairGeometry.from_design)
from ..generated import tca_kernels  # noqa: F401
from ..solver import Solver  # noqa: F401
from ..solver.options import DEFAULT_OPTIONS, SolverOptions  # noqa: F401  (re-exported: tca.SolverOptions)
from .backlash import BACKLASH_PAIRS, BACKLASH_POSITIONS, Backlash, backlash, whole_pitches  # noqa: F401
from .contact import (ERROR_NAMES, ERROR_UNITS, FLANKS, NoContactError, boundary_margins,  # noqa: F401
                      check_flank, contact_boundary_names, contact_margins, contact_points, errors_array, evaluate,
                      geometry_of, newton_tolerance, surface, surface_jacobian, tangent, unknowns)
from .flank import FlankResult, mesh_angles, mesh_flank  # noqa: F401
from .grid import SERIAL_MAX_SETS, GridSolution, solve_grid, solved_contact_points  # noqa: F401
from .options import OptionError, Options  # noqa: F401
from .reference import Reference, first_touch_sign, gap_sign, pitch_point_notes, reference_contact  # noqa: F401
from .result import TCAResult, analyze, run  # noqa: F401
from .sensitivity import sensitivity  # noqa: F401

__all__ = ["analyze", "Backlash", "backlash", "BACKLASH_PAIRS", "BACKLASH_POSITIONS",
           "boundary_margins", "check_flank", "contact_boundary_names", "contact_margins", "contact_points",
           "DEFAULT_OPTIONS", "ERROR_NAMES", "ERROR_UNITS", "errors_array", "evaluate", "first_touch_sign",
           "FlankResult", "FLANKS", "gap_sign", "geometry_of", "GridSolution", "Member", "mesh_angles", "mesh_flank",
           "newton_tolerance", "NoContactError", "OptionError", "Options", "PairGeometry", "pitch_point_notes",
           "Reference", "reference_contact", "run", "sensitivity", "SERIAL_MAX_SETS",
           "solve_grid", "solved_contact_points", "Solver", "SolverOptions", "surface", "surface_jacobian",
           "tangent", "tca_kernels", "TCAResult", "unknowns", "whole_pitches"]

"""The contact solver, written once (split by job into linalg, newton, first_touch, clearance,
paths and gaps; this module is their one namespace and says what the compiled backend does with them): Newton on Eq 38, error homotopy, path continuation,
classification, and the first touch of the bounded flank patches (edge and corner contact).

Every function here is plain Python over floats and small numpy arrays, in the subset that
numba compiles.  :mod:`beveloid.solver.backends` runs the same functions either as they are
("numpy" backend, the reference) or compiled by numba ("compiled" backend).  They reach the
maths only through the generated glue ``tca_kernels_scalar`` (the Eq 38 system of the two
members' surface models and the flank margins), so a new surface model changes nothing here.

A call names what it solves and how by records (:mod:`beveloid.solver.records`): the *problem*
(each member's model and parameter vectors, the placement and the flank blanks: ``Problem``), the
request (``PathRequest``, ``GapRequest``, ``ChordRequest``), the ``Settings`` (tolerances, limits,
the first-touch sign) and the output arrays (``PathOutput``, ``GapOutput``).

**First touch.**  A tooth pair's contact is the extreme gear angle (``sign`` * phi'_2 largest,
``sign`` from tca.gap_sign) over the pairs of points of the two bounded patches that coincide.
When the Eq 38 tangency lies on both patches it is that extreme (surface contact, OK).  Otherwise
:func:`first_touch` looks for the Karush-Kuhn-Tucker point of the problem "maximize sign * phi'_2
subject to R_f1 = R_f2 and the eight margins g_i >= 0" by an active-set iteration over the
candidate systems of ``tca_kernels_scalar.candidate_system_point`` (edge: one active boundary;
corner: two): solve the system of the active set by Newton, add the most violated inactive
boundary, drop an active one whose multiplier (from J^T y = -sign e_phi'2, the rows of J being
the gradients of the constraints) has the wrong sign, until the point is feasible with
non-negative multipliers.  Along a path the previous point's active set and solution, predicted
with the exact tangent, start the next point, so a point usually costs one Newton solve; the
Eq 38 tangency is not solved while an edge contact is followed that way (its multiplier turns
negative where the tangency returns onto the patches, and the search then gives up).  If the
iteration does not settle, every candidate system is solved from the tangency and the extreme
feasible solution is kept (:func:`enumerate_candidates`); none feasible means the patches do
not touch (OUTSIDE).  Before the search from the tangency, :func:`patches_apart` tries to prove
that the pinion's patch cannot reach the gear's at any gear angle (out-of-mesh tooth pairs):
then the point is OUTSIDE at once.
"""
from ..generated.tca_kernels_scalar import (  # noqa: F401  (the kernels the core calls, in its namespace)
    blank_margins_point, candidate_system_point, contact_margin_point, contact_system_point, edge_workspace,
    pinion_in_gear_frame_point, surface_jet_point, surface_point, workspace,
)
from .linalg import copy_into, copy_matrix_into, solve_linear, residual_norm  # noqa: F401
from .newton import (  # noqa: F401
    OK, EDGE, OUTSIDE, FAILED, FINAL_STEP_K, FINAL_STEP_RESIDUAL_MM, GEAR_ANGLE, scratch, evaluate_unchecked,
    evaluate, newton_update, newton, on_patch, classify, homotopy, solve_point,
)
from .first_touch import (  # noqa: F401
    MAX_ROUNDS, TRACK_T1, TRACK_T2, TRACK_H1, TRACK_H2, TRACK_VALID, TRACK_SIZE, edge_scratch,
    evaluate_candidate, newton_candidate, conflicting, multipliers, worst_inactive, first_touch, nearest_turn,
    enumerate_candidates, follow_edge,
)
from .clearance import (  # noqa: F401
    MAX_SPLITS, FORM_LIMIT, CELL_X, CELL_L, CELL_U, CELL_HALF_L, CELL_HALF_U, CELL_STRETCH, clearance_scratch,
    sphere_outside_blank, patches_apart,
)
from .paths import solve_off_patch, solve_paths, contact_points  # noqa: F401
from .gaps import PINION_L, PINION_U, GEAR_L, GEAR_U, normal_gaps  # noqa: F401
from .chord import ellipse_chords  # noqa: F401

#: Functions the compiled backend runs on threads over their error sets (beveloid.solver.threads);
#: ``<name>_serial`` is the function itself, on the calling thread.
PARALLEL = ("solve_paths",)
#: Functions that allocate arrays (here and in the generated glue).  The compiled backend keeps
#: numba's reference counting (NRT) for them only: every other function just works on arrays its
#: caller owns, and without the atomic increments and decrements of their references an
#: evaluation of the contact system costs ~42 % less (0.653 -> 0.381 us, docs/performance.md "What
#: bounds the TCA's time", `benchmarks/profile_sweep.py --repeats 25` on both).  numba refuses to
#: compile a function outside this list that allocates ("NRT required but not enabled").
ALLOCATING = ("scratch", "edge_scratch", "clearance_scratch", "workspace", "edge_workspace", "solve_paths",
              "solve_point", "normal_gaps", "solve_linear", "contact_points", "ellipse_chords")

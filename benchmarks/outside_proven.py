"""docs/validation.md 3: how many of an aligned mesh study's `outside` points the patch-clearance
pre-check proves apart (`core.patches_apart`) before the candidate search.

    python benchmarks/outside_proven.py

Case 1, right flank, 3 pairs x 200 positions (the study of
tests/solver/test_solver_patch_clearance.py::test_outside_points_of_a_mesh_study_cannot_touch, which
holds at least 90 % proven and every outside point clear of the gear blank on dense samples).
Not a test.
"""
import numpy as np

from beveloid import tca
from beveloid.pair import Pair
from beveloid.solver import Solver, patch_cover
from beveloid.status import Status

geom = Pair.example("case1").geometry
flank = tca.analyze(geom, tca.Options(flanks=("right",), positions=200, pairs=3, approach_mm=None)).flanks["right"]
outside = np.array(flank.status) == Status.OUTSIDE.label
core = Solver().core
cover = patch_cover.patch_cover(geom, "pinion", "right").cells
pitch = geom.pitch_angles[0]
apart = [bool(core.patches_apart(geom.problem("right"), cover, phi - pair * pitch, np.zeros(5), 1e-9,
                                 core.clearance_scratch()))
         for phi, pair in zip(flank.pinion_angle[outside], flank.tooth_pair[outside])]
print(f"case 1, right flank, 3 pairs x 200 positions: {outside.sum()} outside points, {sum(apart)} proven apart")

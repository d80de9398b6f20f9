"""A grid angle given twice (issue 57): the loaded TCA's cycle holds pair k's first pinion angle and pair
k-1's last, equal to round-off, and the path solver marches through both.  The second is a step of
~1e-17 rad; the second-order predictor divided by it threw the next prediction hundreds of mm off
the patches, and the entering pair came out OUTSIDE (with a far tangency) or FAILED, depending on the
number of positions, so it carried no load at 30 positions and did at 21."""
from __future__ import annotations


import numpy as np
import pytest

from beveloid import mesh, tca
from beveloid.status import Status
from beveloid.pair import Pair
from beveloid.solver import Solver, backends
from beveloid.tca.flank import mesh_angles
from beveloid.tca.grid import solve_grid

#: an untuned crossed design (m_n 3, 21/38 teeth) whose third pair enters on the gear's tip edge
SPEC = {
    "pair": {"normal_module_mm": 3.0, "normal_pressure_angle_deg": 20.0, "shaft_angle_deg": 13.0, "offset_mm": 90.0},
    "pinion": {"teeth": 21, "cone_angle_deg": 2.0, "helix_angle_deg": 23.0, "profile_shift": 0.15,
               "face_width_mm": 28.0, "lead_crowning_um": 12.0, "tip_relief_um": 8.0},
    "gear": {"teeth": 38, "cone_angle_deg": 0.8, "face_width_mm": 32.0, "end_relief_um": 6.0},
}


@pytest.mark.parametrize("backend", ["numpy", "compiled"] if backends.AVAILABLE else ["numpy"])
@pytest.mark.parametrize("positions", [21, 30])
def test_every_pair_of_the_cycle_is_solved_on_its_branch(backend, positions):
    geom = Pair.from_spec(SPEC).geometry
    solver = Solver(backend)
    phi1 = mesh_angles(geom, "right", positions, 3, 1, solver.options)
    ks, shifted = mesh.pair_angles(phi1, 3, geom.pitch_angles[0])
    repeated = np.abs(np.diff(np.sort(shifted.ravel())))
    assert (repeated < 1e-12).sum() == 2  # the case means something: two angles given twice
    sol = solve_grid(geom, "right", np.zeros((1, 5)), shifted.ravel(), solver=solver)
    status = sol.status[0]
    # the entering pair (k = +1, the lowest angles) is an edge or surface contact at every position,
    # never lost (FAILED) nor called apart (OUTSIDE) after a wandered tangency
    assert set(status.tolist()) <= {Status.OK, Status.EDGE}, np.unique(status, return_counts=True)
    kinematic = (tca.unknowns(tca.reference_contact(geom, "right", solver.options).x).gear_angle_rad
                 - geom.pinion.teeth / geom.gear.teeth * (shifted.ravel() - tca.reference_contact(geom, "right").pinion_angle))
    gear = sol.x[0, :, tca.tca_kernels.UNKNOWNS.index("gear_angle_rad")]
    assert np.all(np.abs(gear - kinematic) < 0.1 * geom.pitch_angles[1])


@pytest.mark.parametrize("backend", ["numpy", "compiled"] if backends.AVAILABLE else ["numpy"])
@pytest.mark.parametrize("span_deg, at", [((-20.0, 3.0), 10), ((-26.0, -10.0), 5)])
def test_a_repeated_angle_changes_no_neighbour(backend, span_deg, at):
    """The same grid with and without one angle given again one ulp on: every other point the same.
    The second span is an edge contact followed without the tangency (first_touch.follow_edge), whose
    predictor had the same division (x off by 1e25 at the next point)."""
    geom = Pair.from_spec(SPEC).geometry
    solver = Solver(backend)
    ref = tca.reference_contact(geom, "right")
    grid = ref.pinion_angle + np.radians(np.linspace(*span_deg, 33))
    twice = np.sort(np.append(grid, np.nextafter(grid[at], np.inf)))  # a step of round-off
    assert 0 < twice[at + 1] - twice[at] < 1e-15
    once = solve_grid(geom, "right", np.zeros((1, 5)), grid, solver=solver)
    both = solve_grid(geom, "right", np.zeros((1, 5)), twice, solver=solver)
    keep = np.r_[0:at + 1, at + 2:twice.size]
    np.testing.assert_array_equal(both.status[0, keep], once.status[0])
    ok = once.status[0] <= Status.EDGE
    assert ok.sum() > 25
    np.testing.assert_allclose(both.x[0, keep][ok], once.x[0][ok], rtol=0, atol=1e-9)
    assert both.status[0, at + 1] == once.status[0, at]

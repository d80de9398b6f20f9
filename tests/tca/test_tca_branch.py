"""A point that carries numbers is a contact of its own tooth pair: on pair 0's branch of the gear angle."""
import numpy as np

from beveloid import tca
from beveloid.generated import tca_kernels
from beveloid.pair import Pair
from beveloid.solver.records import PathOutput
from beveloid.spec import load_example, spec_to_dict
from beveloid.status import Status
from beveloid.tca.grid import BRANCH_PITCHES, off_branch
from beveloid.tca.reference import reference_contact


def test_off_branch_fails_points_a_pitch_or_a_turn_away(geom1):
    ref = reference_contact(geom1, "right")
    grid = ref.pinion_angle + np.array([0.0, 0.01, 0.02, 0.03])
    kin = ref.x[4] - geom1.pinion.teeth / geom1.gear.teeth * (grid - ref.pinion_angle)
    p2 = geom1.pitch_angles[1]
    x = np.tile(ref.x, (1, 4, 1))
    x[0, :, 4] = kin + np.array([0.0, 0.49 * p2, p2, 2 * np.pi])
    out = PathOutput(x=x, status=np.full((1, 4), Status.EDGE, dtype=np.int64), iterations=np.zeros((1, 4), np.int64),
                     boundary=np.zeros((1, 4), np.int64), active=np.zeros((1, 4, 2), np.int64))
    off_branch(geom1, ref, grid, out)
    assert BRANCH_PITCHES == 0.5
    assert list(out.status[0]) == [Status.EDGE, Status.EDGE, Status.FAILED, Status.FAILED]
    assert list(out.boundary[0]) == [0, 0, -1, -1]


def test_crowned_mesh_points_with_numbers_are_on_their_branch():
    # 10 um crowning both members, alpha_n - 1e-13 rad: an edge search once wandered to a gear point
    # 10 m away with TE 0.73 rad and status "edge"
    data = spec_to_dict(load_example("case1"))
    data["pair"]["normal_pressure_angle_deg"] -= np.degrees(1e-13)
    for m in ("pinion", "gear"):
        data[m].update(tooth_surface="crowned", profile_crowning_um=10.0, lead_crowning_um=10.0)
    geom = Pair.from_spec(data).geometry
    fr = tca.mesh_flank(geom, "right", positions=31)
    has = np.isin(fr.status, [Status.OK.label, Status.EDGE.label])
    assert has.sum() > 80
    assert np.all(np.abs(fr.transmission_error[has]) < 0.5 * geom.pitch_angles[1])
    assert np.all(np.isfinite(fr.transmission_error) == has)
    assert tca_kernels.UNKNOWNS[4] == "gear_angle_rad"

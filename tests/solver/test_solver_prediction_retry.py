"""The TCA path (solver.paths.solve_paths) predicts each point from the last one's tangent.  Where a
pinion end relief begins, the tangency stops running along the face and stays at the relief's start (its
face parameter u turns from -0.97 mm a step to -0.05): on a random design (m_n 3, 23/37 teeth, 9 um end
relief on the pinion) the prediction from the turn threw Newton off at 21 positions, and every later
point of that pair, restarted from the reference a pitch away, failed too: the pair carried no load over
three quarters of the cycle and its neighbour carried 9400 N alone, its root stress 32 % above the
30-position run's.  A prediction that fails is now retried from the last solution itself."""
from __future__ import annotations

import numpy as np

from beveloid import tca
from beveloid.pair import Pair
from beveloid.solver import Solver
from beveloid.spec import spec_from_dict
from beveloid.status import PointStatus

SPEC = {
    "pair": {"normal_module_mm": 3.0, "normal_pressure_angle_deg": 22.5, "shaft_angle_deg": 6.7, "offset_mm": 97.9},
    "pinion": {"teeth": 23, "cone_angle_deg": 0.5, "helix_angle_deg": 28.0, "profile_shift": 0.3, "face_width_mm": 22.0,
               "profile_crowning_um": 8.0, "end_relief_um": 9.0},
    "gear": {"teeth": 37, "cone_angle_deg": 1.0, "face_width_mm": 22.0},
    "misalignment": {"horizontal_deg": -0.002},
}


def test_a_failed_prediction_is_retried_from_the_last_solution():
    pair = Pair.from_spec(spec_from_dict(SPEC))
    for n in (21, 30):
        fr = tca.mesh_flank(pair.geometry, "right", pair.errors, positions=n, pairs=3, window_pitches=1,
                            solver=Solver.of(None))
        status = np.asarray(fr.status, dtype=object).reshape(3, n)
        assert not (status == PointStatus.FAILED).any(), f"{n} positions: {status.tolist()}"
        # pair -1 (the one leaving) runs on the flank to the relief's start, then onto an edge: its contact
        # (the tangency, then the edge contact) moves steadily, never far
        u = fr.unknowns.reshape(3, n, 5)[0, :, 1]
        assert np.all(np.isfinite(u)) and np.all(np.abs(np.diff(u)) < 1.0)

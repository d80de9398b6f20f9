"""Edge and corner contacts lie on the gear angle's branch of the pair's tangency (issue 12):
every candidate system is 2 pi-periodic in phi'_2, so a search that converged whole turns away
is turned back (core.nearest_turn) instead of winning the 'extreme phi'_2' comparison."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from beveloid import tca
from beveloid.solver import backends
from beveloid.pair import Pair

ROOT = Path(__file__).resolve().parents[2]
GEAR_ANGLE = tca.tca_kernels.UNKNOWNS.index("gear_angle_rad")


@pytest.mark.parametrize("backend", ["numpy", "compiled"] if backends.AVAILABLE else ["numpy"])
@pytest.mark.parametrize("turns", [-3, -1, 0, 2, 1000])
def test_nearest_turn_removes_whole_turns_only(backend, turns):
    ns = backends.namespace(backend)
    x = np.array([1.0, 2.0, 3.0, 4.0, 0.3 + 2 * math.pi * turns])
    ns.nearest_turn(x, 0.1)
    assert x[GEAR_ANGLE] == pytest.approx(0.3, abs=1e-9) and list(x[:4]) == [1.0, 2.0, 3.0, 4.0]
    y = np.array([0.0, 0.0, 0.0, 0.0, 0.1 + math.pi - 1e-6])  # within pi already: unchanged
    ns.nearest_turn(y, 0.1)
    assert y[GEAR_ANGLE] == 0.1 + math.pi - 1e-6


def test_edge_contacts_stay_within_a_pitch_of_the_tangency_branch():
    """Case 1 under the paper's largest errors, 3 pairs: every solved contact's gear angle is
    within a few gear pitches of the aligned reference (the neighbour pairs are one pitch away;
    a whole turn would be 45 pitches)."""
    geom = Pair.from_spec(ROOT / "examples" / "case1.toml").geometry
    p2 = geom.pitch_angles[1]
    for errors in ([1.0, 1.0, 1.0, 0.0, 0.0], [0.0, 0.0, 0.0, 0.0, math.radians(-0.03)],
                   [0.0, 0.0, 0.0, math.radians(-0.2), 0.0]):
        res = tca.analyze(geom, tca.Options(positions=60, pairs=3, approach_mm=None, errors=errors))
        for flank, fr in res.flanks.items():
            ref = tca.unknowns(tca.reference_contact(geom, flank).x).gear_angle_rad
            phi2 = fr.gear_angle[np.isfinite(fr.gear_angle)]
            assert phi2.size and np.abs(phi2 - ref).max() < 4 * p2
            assert np.isfinite(fr.te_peak_to_peak) and fr.te_peak_to_peak < 1e-3

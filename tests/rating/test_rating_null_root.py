"""The rating's local values where the FE tooth has none to give: a member whose root fillet reads no
tensile stress over the cycle (a face a millimetre wide carried at its edge: found by the loaded-path
fuzz) gets null root stress and S_F with a note, never a division by zero or a float of None."""
from __future__ import annotations

import numpy as np

from beveloid import ltca
from beveloid.pair import Pair
from beveloid.rating.analysis import loaded_contact
from beveloid.solver import Solver


class _FeReading:
    """An LTCA result (plate tooth, cheap) read as if its FE tooth had given these root stresses."""

    def __init__(self, result, top, where):
        self._result, self._top, self._where = result, top, where
        self.tooth_model = "fe"

    def __getattr__(self, name):
        return getattr(self._result, name)

    def root_stress_max_mpa(self):
        return self._top

    def root_stress_location(self):
        return self._where


def test_no_tensile_root_stress_and_an_unknown_place_are_null_not_an_error():
    pair = Pair.example("case1")
    lt = ltca.analyze(pair, ltca.LoadCase(200.0), ltca.Options(positions=2, grid=(5, 5), tooth_model="plate"), solver=Solver())
    unknown = {"position": 0, "pair": 0, "z_mm": None, "height_mm": None, "flank": lt.flank}
    lc = loaded_contact(_FeReading(lt, {"pinion": 0.0, "gear": 50.0}, {"pinion": unknown, "gear": unknown}),
                        pair.geometry, 30.0)
    assert lc.root_stress_max_mpa == {"pinion": None, "gear": 50.0}
    assert lc.root_stress_location["pinion"] is None
    assert lc.root_stress_location["gear"]["face_z_mm"] is None
    assert lc.root_stress_location["gear"]["height_above_root_mm"] is None
    assert np.isfinite(lc.root_stress_location["gear"]["pinion_angle_rad"])
    assert any(n.startswith("pinion: the FE tooth reads no tensile root stress") for n in lc.notes)

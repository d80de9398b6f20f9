"""The FPD angle of Eqs 18-20 against the real surfaces: the crossing angle of the two flanks'
zero-curvature principal directions at the solved pitch-point contact, over many designs."""
import math
from pathlib import Path

import numpy as np
import pytest

from beveloid import curvature, tca
from beveloid.design import design
from beveloid.generated import placement
from beveloid.spec import load_spec

ROOT = Path(__file__).resolve().parents[2]
BASE = (ROOT / "examples" / "case1.toml").read_text()


def crossing_angle_deg(geom, flank):
    """Acute angle between the pinion's and the gear's zero-curvature principal directions in S_f
    at the aligned contact at the pitch point."""
    ref = tca.reference_contact(geom, flank)
    x = ref.x
    d1 = curvature.principal_curvatures(geom, "pinion", flank, x[0], x[1]).d2
    d2 = curvature.principal_curvatures(geom, "gear", flank, x[2], x[3]).d2
    L1 = placement.pinion_placement(ref.pinion_angle, geom.placement()).rotation
    L2 = placement.gear_placement(x[4], np.zeros(5), geom.placement()).rotation
    c = abs((L1 @ d1) @ (L2 @ d2))
    return math.degrees(math.acos(min(1.0, c)))


def _variant(helix, cone1, cone2, shaft):
    text = BASE.replace("helix_angle_deg = 23.0", f"helix_angle_deg = {helix}")
    text = text.replace("cone_angle_deg = 2.0", f"cone_angle_deg = {cone1}")
    text = text.replace("cone_angle_deg = 0.8", f"cone_angle_deg = {cone2}")
    return text.replace("shaft_angle_deg = 13.0", f"shaft_angle_deg = {shaft}")


DESIGNS = [(23.0, 2.0, 0.8, 13.0), (22.0, 1.0, 1.5, 13.0), (24.0, 3.0, 0.5, 13.0), (23.0, -1.0, 2.0, 12.5),
           (23.5, 2.5, 1.0, 13.5)]


@pytest.mark.parametrize("params", DESIGNS, ids=[f"beta{d[0]}-g{d[1]}-{d[2]}-d{d[3]}" for d in DESIGNS])
def test_crossing_of_principal_directions_is_the_fpd_angle(tmp_path, params):
    f = tmp_path / "d.toml"
    f.write_text(_variant(*params))
    res = design(load_spec(f))
    geom = tca.PairGeometry.from_design(res)
    for flank, xi in (("left", res.fpd_angle_left), ("right", res.fpd_angle_right)):
        xi_deg = math.degrees(abs(xi)) % 180
        xi_deg = min(xi_deg, 180 - xi_deg)
        assert crossing_angle_deg(geom, flank) == pytest.approx(xi_deg, abs=1e-7), (flank, params)

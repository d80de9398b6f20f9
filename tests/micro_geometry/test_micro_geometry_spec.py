"""The micro-geometry keys in the spec: selection of the model, composition with crowning, the
shape names, the design-dependent bounds and the round trip."""
from __future__ import annotations

import tomllib
from pathlib import Path

import pytest

from beveloid.pair import Pair
from beveloid.spec import SpecError, spec_from_dict, spec_to_dict

ROOT = Path(__file__).resolve().parents[2]


def case1(**pinion):
    data = tomllib.loads((ROOT / "examples" / "case1.toml").read_text())
    data["pinion"].update(pinion)
    return data


def test_a_relief_amount_selects_the_model_and_crowning_composes():
    spec = spec_from_dict(case1(tip_relief_um=20.0, profile_crowning_um=5.0))
    assert spec.pinion.tooth_surface == "micro_geometry" and spec.gear.tooth_surface == "involute"
    opts = dict(spec.pinion.surface_options)
    assert opts["tip_relief_um"] == 20.0 and opts["profile_crowning_um"] == 5.0
    assert opts["tip_relief_shape"] == "parabolic"  # the default name
    # crowning alone still selects "crowned"
    assert spec_from_dict(case1(lead_crowning_um=5.0)).pinion.tooth_surface == "crowned"
    assert spec_from_dict(case1(lead_slope_um=-3.0)).pinion.tooth_surface == "micro_geometry"


def test_shape_names_reach_the_kernels_as_exponents():
    geom = Pair.from_spec(case1(tip_relief_um=20.0, tip_relief_shape="linear")).geometry
    values = geom.surface_values("pinion")
    assert (values["tip_relief_shape"], values["end_relief_shape"]) == (1.0, 2.0)


def test_round_trip():
    spec = spec_from_dict(case1(end_relief_um=10.0, end_relief_length_mm=5.0, end_relief_shape="linear"))
    assert spec_from_dict(spec_to_dict(spec)) == spec


@pytest.mark.parametrize("keys, bad", [
    (dict(tip_relief_shape="cubic"), "pinion.tip_relief_shape"),
    (dict(tip_relief_um=-1.0), "pinion.tip_relief_um"),
    (dict(lead_slope_um=250.0), "pinion.lead_slope_um"),
    (dict(tip_relief_um=10.0, tip_relief_height_mm=20.0), "pinion.tip_relief_height_mm"),  # working depth 12 mm
    (dict(end_relief_um=10.0, end_relief_length_mm=25.0), "pinion.end_relief_length_mm"),  # half the face: 25 mm
    (dict(tooth_surface="crowned", tip_relief_um=10.0), "pinion.tip_relief_um"),
])
def test_bad_values_are_refused_in_one_line(keys, bad):
    with pytest.raises(SpecError) as e:
        spec_from_dict(case1(**keys))
    msg = str(e.value)
    assert bad in msg and "\n" not in msg

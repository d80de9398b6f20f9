"""The facade: Pair.from_spec builds the same design and geometry as the chain it replaces."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from beveloid.design import DesignError, design
from beveloid.geometry import PairGeometry
from beveloid.pair import Pair
from beveloid.spec import SpecError, load_spec, spec_to_dict

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("case", ["case1", "case2"])
def test_every_source_gives_the_chain_it_replaces(case):
    path = ROOT / "examples" / f"{case}.toml"
    spec = load_spec(path)
    chain = PairGeometry.from_design(design(spec))
    for source in (path, str(path), spec, spec_to_dict(spec)):
        pair = Pair.from_spec(source)
        assert pair.spec == spec
        assert pair.geometry == chain
        assert pair.design.working_normal_pressure_angle == design(spec).working_normal_pressure_angle
    assert Pair.example(case).geometry == chain


def test_errors_are_the_misalignment_in_mm_and_rad():
    data = spec_to_dict(load_spec(ROOT / "examples" / "case1.toml"))
    data["misalignment"] = {"dx_mm": 0.5, "horizontal_deg": 0.01}
    e = Pair.from_spec(data).errors
    np.testing.assert_allclose(e, [0.5, 0.0, 0.0, 0.0, np.radians(0.01)], rtol=0, atol=1e-15)


def test_bad_sources_are_refused():
    with pytest.raises(SpecError, match="no such file"):
        Pair.from_spec(ROOT / "examples" / "missing.toml")
    with pytest.raises(TypeError, match="path, a DesignSpec or a mapping"):
        Pair.from_spec(42)
    data = spec_to_dict(load_spec(ROOT / "examples" / "case1.toml"))
    data["pair"]["offset_mm"] = 1.0  # no working pressure angle for so small an offset
    with pytest.raises((DesignError, SpecError)):
        Pair.from_spec(data)

"""tca.Options (the range table the CLI reads), one position, and long faces."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from beveloid import cli, tca
from beveloid.solver import Solver

CASE1 = str(Path(__file__).resolve().parents[2] / "examples" / "case1.toml")


@pytest.mark.parametrize("kw, key", [(dict(positions=0), "positions"), (dict(pairs=2), "pairs"),
                                     (dict(pairs=11), "pairs"), (dict(flanks=("up",)), "flanks"),
                                     (dict(positions=2.5), "positions"), (dict(approach_mm=0.0), "approach_mm"),
                                     (dict(errors=(0.1, 0.2)), "errors"),
                                     (dict(errors=(0, 0, float("nan"), 0, 0)), "errors"),
                                     (dict(errors="dx"), "errors")])
def test_options_refuse_out_of_range(kw, key):
    with pytest.raises(ValueError, match=key):
        tca.Options(**kw)


def test_one_position_is_the_reference_angle_without_te_statistics(pair1):
    res = tca.analyze(pair1, tca.Options(positions=1, pairs=3, approach_mm=None), solver=Solver())
    for flank, fr in res.flanks.items():
        ref = tca.reference_contact(pair1.geometry, flank)
        assert fr.pinion_angle[fr.tooth_pair == 0][0] == ref.pinion_angle
        assert fr.status[1] == "ok" and abs(fr.transmission_error[1]) < 1e-12  # pair 0 at the pitch point
        assert np.isnan(fr.te_peak_to_peak)
    o = res.to_json()
    assert o["te_peak_to_peak_urad"] == {"left": None, "right": None}
    assert any("not available from one position" in n for n in o["notes"])


def test_cli_tca_one_position(capsys):
    assert cli.main(["tca", CASE1, "--positions", "1", "--json"]) == 0
    o = json.loads(capsys.readouterr().out)
    assert len(o["flanks"]["right"]["status"]) == 3 and o["te_peak_to_peak_urad"]["right"] is None
    assert cli.main(["tca", CASE1, "--positions", "1"]) == 0
    text = capsys.readouterr().out
    assert "n/a" in text and "not available from one position" in text


@pytest.mark.parametrize("face_mm", [500.0, 1000.0])
def test_long_pinion_face_has_a_bounded_patch(tmp_path, capsys, face_mm):
    src = Path(CASE1).read_text(encoding="utf-8")
    head, rest = src.split("face_width_mm", 1)
    path = tmp_path / "long.toml"
    path.write_text(head + f"face_width_mm = {face_mm}" + rest.split("\n", 1)[1], encoding="utf-8")
    assert cli.main(["tca", str(path), "--positions", "5", "--flank", "right", "--json"]) == 0
    o = json.loads(capsys.readouterr().out)
    assert set(o["flanks"]["right"]["status"]) <= {"ok", "edge", "outside"}
    assert "ok" in o["flanks"]["right"]["status"]


def test_errors_in_options_are_the_errors_analysed(geom1):
    """analyze(geometry, Options(errors=...)) solves under those errors: the same numbers as the
    flank's mesh study under them; a PairGeometry without them is the aligned pair."""
    e = (0.2, -0.1, 0.3, 0.0, 1e-4)
    new = tca.analyze(geom1, tca.Options(flanks=("right",), positions=9, pairs=1, approach_mm=None, errors=e),
                      solver=Solver("numpy"))
    alone = tca.mesh_flank(geom1, "right", e, positions=9, pairs=1, solver=Solver("numpy"))
    assert list(new.errors) == list(e)
    np.testing.assert_array_equal(new.flanks["right"].transmission_error, alone.transmission_error)
    aligned = tca.analyze(geom1, tca.Options(flanks=("right",), positions=3, pairs=1, approach_mm=None), solver=Solver("numpy"))
    assert not aligned.errors.any()
    with pytest.raises(TypeError, match="positions"):
        tca.analyze(geom1, tca.Options(), positions=3)

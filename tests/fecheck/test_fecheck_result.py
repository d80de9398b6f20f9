"""fe_check's result (beveloid/fecheck/result.py): frozen all the way down, and its to_json() the contract's
JSON (missing numbers null, the blocks and lists in the contract's order). The end-to-end run that fills one
from CalculiX is test_fecheck_cli.py's (slow)."""
from __future__ import annotations

import dataclasses
import json
import math

import pytest

from beveloid import ltca as lt
from beveloid.fecheck.check import Options
from beveloid.fecheck.result import CheckResult, ContactNumbers


def _result(about):
    calculix = ContactNumbers.of([10.0, None], [900.0, math.inf], [0.5, 0.0], 12.5, {"pinion": 300.0, "gear": None},
                                 200.0)
    ltca = ContactNumbers.of([11.0, 1.0], [950.0, 80.0], [0.4, 0.1], math.nan, {"pinion": None, "gear": 250.0}, 199.0)
    return CheckResult("2.21", 3, 0.25, "plate",
                       (0, 1), -1.5, 1000, 4000, 1.0, 2.0, 3.0, calculix, ltca, {"deck": "d.inp"}, ["a note"],
                       [1000.0, None], [[0.2, 5.0], [0.1, math.nan]], about,
                       options=Options(ltca=lt.Options(flank="left"), refinement=2), load=lt.LoadCase(200.0))


def test_to_json_writes_the_contract():
    about = [{"tooth_pair": 0, "semi_axes_mm": [0.2, 5.0], "size_mm": 0.07}]
    out = _result(about).to_json()
    assert list(out) == ["calculix_version", "position", "pinion_angle_rad", "torque_nm", "flank", "ltca_tooth_model",
                         "refinement", "tooth_pairs", "unloaded_transmission_error_urad", "elements", "dof",
                         "calculix_wall_s", "calculix_cpu_s", "mesh_s", "calculix", "ltca", "root_stress_agreement",
                         "files", "notes",
                         "ltca_hertz_max_pressure_mpa", "ltca_patch_semi_axes_mm", "local_refinement"]
    assert (out["torque_nm"], out["flank"], out["refinement"], out["tooth_pairs"]) == (200.0, "left", 2, [0, 1])
    assert out["calculix"] == {"pair_normal_load_n": [10.0, None], "pair_max_pressure_mpa": [900.0, None],
                               "contact_area_mm2": [0.5, 0.0], "loaded_transmission_error_urad": 12.5,
                               "root_stress_max_mpa": {"pinion": 300.0, "gear": None},
                               "moment_about_pinion_axis_nm": 200.0}
    assert out["ltca"]["loaded_transmission_error_urad"] is None
    assert out["ltca"]["root_stress_max_mpa"] == {"pinion": None, "gear": 250.0}
    assert out["root_stress_agreement"]["pinion"] == {"calculix_mpa": 300.0, "ltca_mpa": None, "ratio": None,
                                                      "agrees": None}
    assert out["ltca_hertz_max_pressure_mpa"] == [1000.0, None]
    assert out["ltca_patch_semi_axes_mm"] == [[0.2, 5.0], [0.1, None]]
    assert out["local_refinement"] == about and out["files"] == {"deck": "d.inp"} and out["notes"] == ["a note"]
    assert json.loads(json.dumps(out, allow_nan=False)) == out
    assert _result(None).to_json()["local_refinement"] is None


def test_the_result_is_frozen_all_the_way_down():
    about = [{"tooth_pair": 0, "semi_axes_mm": [0.2, 5.0]}]
    r = _result(about)
    about[0]["tooth_pair"] = 7  # the caller's list is not the result's
    assert r.local_refinement[0]["tooth_pair"] == 0
    with pytest.raises(dataclasses.FrozenInstanceError):
        r.position = 4
    for a in (r.calculix.pair_normal_load_n, r.ltca.contact_area_mm2, r.ltca_patch_semi_axes_mm):
        with pytest.raises(ValueError):
            a[0] = 1.0
    for m in (r.files, r.calculix.root_stress_max_mpa, r.local_refinement[0]):
        with pytest.raises(TypeError):
            m["x"] = 1
    assert isinstance(r.notes, tuple) and isinstance(r.local_refinement[0]["semi_axes_mm"], tuple)

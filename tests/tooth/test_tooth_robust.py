"""The whole-tooth checks on designs whose sections leave the formulas' domains (issue 29, item 1):
a tip circle inside the base circle (no involute up to the tip), pointed and undercut ends in one
member.  Nothing crashes, nothing warns, a value that cannot be computed is null with a status."""
from __future__ import annotations

import contextlib
import io
import json
import math
import tomllib
import warnings

import numpy as np
import pytest

from beveloid import cli
from beveloid.pair import Pair
from beveloid.spec import example_text
from beveloid.tooth import report, sections, tip


def _case1(**pinion):
    d = tomllib.loads(example_text("case1"))
    d["pinion"].update(pinion)
    return d


#: case 1 with the longest documented pinion face: undercut and no involute at the toe, pointed at the heel
LONG = _case1(face_width_mm=900.0)


@pytest.fixture(scope="module")
def long_pair():
    return Pair.from_spec(LONG)


@pytest.fixture(scope="module")
def long_result(long_pair):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no numpy RuntimeWarning may reach the user
        return report.analyze(long_pair)


def test_segments_find_the_domain_edge_and_the_root_around_nan():
    """sqrt(x) - 1 on [-1, 3]: NaN below 0 (its domain's edge), <= 0 up to 1, > 0 after: both ends exact."""
    f = lambda x: math.sqrt(x) - 1 if x >= 0 else math.nan  # noqa: E731
    grid = np.linspace(-1.0, 3.0, 9)  # neither 0 nor 1 lies between the same neighbours as a sign change
    segs = sections.segments(f, grid + 0.01, xtol=1e-13)
    assert [c for _, _, c in segs] == [sections.INVALID, sections.NOT_POSITIVE, sections.POSITIVE]
    assert segs[0][1] == pytest.approx(0.0, abs=1e-12)
    assert segs[1][1] == pytest.approx(1.0, abs=1e-12)


def test_toe_without_involute_is_null_with_its_status(long_pair, long_result):
    g = long_pair.geometry
    t = long_result.tip["pinion"]
    w = sections.half_face(g, "pinion")
    toe = sections.section(g, "pinion", -w)
    # the reason, from the section's own radii: the tip circle lies inside both base circles at the toe
    assert float(toe.tip_radius) < min(float(toe.base_radius_left), float(toe.base_radius_right))
    assert t.toe_mm is None and t.middle_mm > 0 and t.heel_mm < 0
    (lo, hi), = t.no_involute
    assert lo == -w
    edge = sections.section(g, "pinion", hi)  # the range ends where the tip circle meets the larger base circle
    assert float(edge.tip_radius) == pytest.approx(max(float(edge.base_radius_left), float(edge.base_radius_right)),
                                                   abs=1e-8)
    names = [s for s, _ in long_result.statuses]
    assert "tip inside base circle" in names and "pointed" in names and "undercut" in names


def test_pointed_heel_meets_where_the_arc_thickness_is_zero(long_pair, long_result):
    t = long_result.tip["pinion"]
    assert t.pointed and t.pointed_to_mm == pytest.approx(sections.half_face(long_pair.geometry, "pinion"))
    assert float(tip.thickness(long_pair.geometry, "pinion", t.pointed_from_mm)) == pytest.approx(0.0, abs=1e-9)
    th = sections.thickness_at_radius(long_pair.geometry, "pinion", t.min_at_mm, t.pointed_tip_radius_mm)
    assert float(th.thickness_angle) == pytest.approx(0.0, abs=1e-12)


def test_design_cli_prints_strict_json_and_dashes(tmp_path, long_result):
    path = tmp_path / "long.toml"
    path.write_text(example_text("case1").replace("face_width_mm = 50.0", "face_width_mm = 900.0"))
    out = {}
    for flag in ("--json", None):
        buf, err = io.StringIO(), io.StringIO()
        with warnings.catch_warnings(record=True) as caught, contextlib.redirect_stdout(buf), \
                contextlib.redirect_stderr(err):
            warnings.simplefilter("always")
            rc = cli.main(["design", str(path)] + ([flag] if flag else []))
        assert rc == 0 and not caught and not err.getvalue(), (rc, caught, err.getvalue())
        out[flag] = buf.getvalue()
    data = json.loads(out["--json"], parse_constant=lambda c: pytest.fail(f"{c} in the JSON"))
    json.dumps(data, allow_nan=False)
    assert data["pinion"]["tip_transverse_thickness_mm"]["toe"] is None
    assert "tip inside base circle" in [s["status"] for s in data["tooth_status"]]
    row = next(line for line in out[None].splitlines() if line.startswith("pinion | left |"))
    assert row.split("|")[2].split("/")[0].strip() == "-"
    assert "nan" not in out[None].lower()


#: sharp racks, undercut gear (0.69 mm at the toe) whose flank carries an end relief: the relieved flank
#: misses the unrelieved fillet's loop at the toe, where its form limit is the body's crossing
RELIEVED_UNDERCUT = {
    "pair": {"normal_module_mm": 2.5, "normal_pressure_angle_deg": 20.0, "shaft_angle_deg": 11.0, "offset_mm": 57.0},
    "pinion": {"teeth": 23, "cone_angle_deg": 3.0, "helix_angle_deg": 18.0, "profile_shift": 0.2,
               "face_width_mm": 22.0, "cutter_tip_radius_coefficient": 0.0, "cutter_addendum_coefficient": 1.25},
    "gear": {"teeth": 37, "cone_angle_deg": 1.5, "face_width_mm": 26.0, "cutter_tip_radius_coefficient": 0.0,
             "cutter_addendum_coefficient": 1.125, "end_relief_um": 8.0, "end_relief_length_mm": 3.0},
}


def test_a_relieved_flank_off_its_fillets_loop_takes_its_bodys_form_limit():
    from beveloid.tooth import body, profile
    from beveloid.tooth.sampling import ToothSampler

    geometry = Pair.from_spec(RELIEVED_UNDERCUT).geometry
    toe = min(ToothSampler(geometry, "gear").z_range_mm)
    got = profile.form_limit(geometry, "gear", "left", toe)
    want = profile.form_limit(body.body_pair(geometry, "gear"), "gear", "left", toe)
    assert want is not None and got == want
    # and the tooth is built: the relieved flank runs into the fillet from there (it raised "no involute")
    ToothSampler(geometry, "gear").check_buildable(np.linspace(toe, -toe, 5))

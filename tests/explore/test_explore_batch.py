"""The batched design and sensitivities equal design() and tca.sensitivity, design by design."""
from __future__ import annotations

import copy

import numpy as np
import pytest

from beveloid import assembly_errors, tca
from beveloid.design import DesignError, Outcome, design, design_arrays, spec_values
from beveloid.errors import ErrorCode
from beveloid.design.report import design_json
from beveloid.spec import SpecError
from beveloid.explore import rows
from beveloid.explore.grid import Plan, parse_vary
from beveloid.pair import Pair
from beveloid.spec import load_example, spec_to_dict
from beveloid.sweep import DEFAULT_RANGES

RTOL = 1e-12


@pytest.fixture(scope="module")
def explored():
    """A grid over cone angle, helix angle and offset of case 1 that holds feasible designs and
    several kinds of refusal (zero cone angle, pointed teeth, pitch point off the profile, ...)."""
    plan = Plan(spec_to_dict(load_example("case1")), (parse_vary("pinion.cone_angle_deg=-4:6:6"),
                                                      parse_vary("pinion.helix_angle_deg=5:45:4"),
                                                      parse_vary("pair.offset_mm=120:229:2")))
    cols = rows.compute(plan, 0, plan.count, DEFAULT_RANGES)
    values = {k: np.full(plan.count, v) for k, v in plan.base_values().items()}
    values.update(plan.values(0, plan.count))
    return plan, cols, values


def _close(a, b, scale=None):
    scale = max(1.0, abs(b)) if scale is None else scale
    return abs(a - b) <= RTOL * scale


def test_statuses_and_working_data_equal_design(explored):
    plan, cols, values = explored
    seen = set()
    for j in range(plan.count):
        try:
            spec = rows.design_spec(plan, values, j)
        except SpecError as err:  # the spec itself refuses a zero cone angle (a cylinder: apex at infinity)
            assert "cone_angle_deg = 0.0" in str(err) and cols["status"][j] == "zero_cone_angle"
            assert np.isnan(cols["working_normal_pressure_angle_deg"][j])
            seen.add("zero_cone_angle")
            continue
        try:
            result = design(spec)
        except DesignError as err:
            seen.add(err.outcome.label)
            assert cols["status"][j] == err.outcome.label, str(err)
            assert np.isnan(cols["working_normal_pressure_angle_deg"][j])
            assert np.isnan(cols["left_pinion_contact_z_mm_per_dx_mm"][j])
            continue
        seen.add("ok")  # passes the design's checks; the whole tooth's may still flag it
        assert cols["status"][j] in ("ok", "pointed", "undercut", "tooth_check_failed")
        assert cols["tooth_status"][j] or cols["status"][j] == "ok"
        out = design_json(result)
        for key in ("working_normal_pressure_angle_deg", "fpd_angle_left_deg", "fpd_angle_right_deg",
                    "normal_angular_factor", "offset_residual_mm"):
            assert _close(cols[key][j], out[key], 1.0), key
        for member in ("pinion", "gear"):
            for key, value in out[member].items():
                if f"{member}_{key}" in cols:
                    assert _close(cols[f"{member}_{key}"][j], value), (member, key)
        assert cols["max_fpd_angle_deg"][j] == max(abs(out["fpd_angle_left_deg"]), abs(out["fpd_angle_right_deg"]))
    # the grid reaches the refusals the issue names, and others
    assert {"ok", "zero_cone_angle", "pitch_point_off_active_profile", "pointed_teeth"} <= seen


def test_sensitivities_equal_tca_sensitivity(explored):
    plan, cols, values = explored
    ok = np.nonzero(cols["status"] == "ok")[0]
    assert ok.size >= 8
    tol = np.abs(assembly_errors.to_layout(DEFAULT_RANGES))
    for j in ok[:: max(1, ok.size // 8)]:
        geom = Pair.from_spec(rows.design_spec(plan, values, j)).geometry
        for flank in tca.FLANKS:
            s = tca.sensitivity(geom, flank)
            assert cols[f"{flank}_contact_status"][j] == s["status"]
            for member in ("pinion", "gear"):
                D = s[f"{member}_contact_D_errors"]
                scale = np.abs(D).max()
                for a, axis in enumerate(rows.AXES):
                    for e, err in enumerate(tca.ERROR_NAMES):
                        assert _close(cols[f"{flank}_{member}_contact_{axis}_mm_per_{err}"][j], D[a, e], scale)
                worst = np.abs(D[2]) @ tol
                assert _close(cols[f"{flank}_worst_{member}_path_shift_mm"][j], worst, worst)
            G = s["gear_angle_D_errors"]
            for e, err in enumerate(tca.ERROR_NAMES):
                assert _close(cols[f"{flank}_gear_angle_rad_per_{err}"][j], G[e], np.abs(G).max())


def test_batch_does_not_depend_on_its_neighbours(explored):
    """A design's row is the same computed alone or in a chunk (what makes any chunking give the same rows)."""
    plan, cols, _ = explored
    for j in (0, 7, plan.count - 1):
        alone = rows.compute(plan, j, j + 1, DEFAULT_RANGES)
        for key, v in alone.items():
            if np.asarray(v).dtype.kind == "f":
                np.testing.assert_array_equal(v[0], cols[key][j], err_msg=key)  # bit for bit
            else:
                assert v[0] == cols[key][j], key


def test_every_refusal_names_its_outcome(explored):
    """design() says which check refused a design by a named outcome (never by its message text), and
    the outcome is the one beveloid.design.design_arrays gives the same spec values."""
    plan, cols, values = explored
    for j in range(plan.count):
        try:
            spec = rows.design_spec(plan, values, j)
            design(spec)
        except SpecError:
            continue
        except DesignError as err:
            assert isinstance(err.outcome, Outcome) and err.outcome is not Outcome.OK
            assert err.code is ErrorCode.DESIGN_REFUSED
            one = design_arrays(spec_values(spec))
            assert Outcome(int(one.outcome[0])) is err.outcome


def test_flank_modification_keys_choose_the_surface_model():
    """Varying a crowning key from 0 gives involute designs at 0 and crowned ones elsewhere (the spec's
    rule when the file does not name tooth_surface), each equal to tca.sensitivity of its own spec."""
    base = spec_to_dict(load_example("case1"))
    for member in ("pinion", "gear"):
        base[member].pop("tooth_surface", None)
    plan = Plan(base, (parse_vary("gear.lead_crowning_um=0:20:2"),))
    cols = rows.compute(plan, 0, 2, DEFAULT_RANGES)
    values = {k: np.full(2, v) for k, v in plan.base_values().items()}
    values.update(plan.values(0, 2))
    assert [m for _, m in rows.models(plan, values)] == ["involute", "crowned"]
    first = []
    for j in range(2):
        spec = rows.design_spec(plan, values, j)
        assert spec.gear.tooth_surface == ("involute", "crowned")[j]
        s = tca.sensitivity(Pair.from_spec(spec).geometry, "right")
        D = s["pinion_contact_D_errors"]
        got = np.array([[cols[f"right_pinion_contact_{a}_mm_per_{e}"][j] for e in tca.ERROR_NAMES] for a in rows.AXES])
        np.testing.assert_allclose(got, D, rtol=0, atol=RTOL * np.abs(D).max())
        first.append(got[2, 0])
    assert abs(first[0] - first[1]) > 1.0  # the crowning changes the path's sensitivity (18.7 -> 6.9 mm/mm)


def test_an_implied_micro_geometry_flank_is_the_one_written_out():
    """Profile crowning and a tip relief without tooth_surface make a micro_geometry flank (the spec's rule:
    the model that takes every key given): its rows are those of the same spec with the model written out."""
    implied = spec_to_dict(load_example("case1"))
    for member in ("pinion", "gear"):
        implied[member].pop("tooth_surface", None)
    implied["pinion"].update(profile_crowning_um=6.0, tip_relief_um=8.0)
    written = copy.deepcopy(implied)
    written["pinion"]["tooth_surface"] = "micro_geometry"
    vary = (parse_vary("pinion.helix_angle_deg=20:26:2"),)
    got, expected = (rows.compute(Plan(base, vary), 0, 2, DEFAULT_RANGES) for base in (implied, written))
    assert list(got) == list(expected)
    for k, v in expected.items():
        np.testing.assert_array_equal(got[k], v, err_msg=k)
    # per design, as the spec decides it for the design's own keys (here the relief varied from 0: crowned)
    plan = Plan(implied, (parse_vary("pinion.tip_relief_um=0:8:2"), parse_vary("gear.lead_slope_um=0:3:2")))
    values = {k: np.full(plan.count, v) for k, v in plan.base_values().items()}
    values.update(plan.values(0, plan.count))
    by_spec = [(s.pinion.tooth_surface, s.gear.tooth_surface)
               for s in (rows.design_spec(plan, values, j) for j in range(plan.count))]
    assert rows.models(plan, values) == by_spec
    assert by_spec[0] == ("crowned", "involute") and by_spec[3] == ("micro_geometry", "micro_geometry")


@pytest.fixture(scope="module")
def face_widths():
    """Case 1 at pinion face widths 100 and 700 mm: the 700 mm design is pointed at the heel and undercut
    at the toe (issue 29 item 3)."""
    plan = Plan(spec_to_dict(load_example("case1")), (parse_vary("pinion.face_width_mm=100:700:2"),))
    return plan, rows.compute(plan, 0, plan.count, DEFAULT_RANGES)


def test_rows_carry_the_whole_tooth_statuses_of_design(face_widths):
    """A row carries the statuses `beveloid design` reports (beveloid.tooth.report.analyze, the one
    implementation), and a pointed or undercut design is not ok, says why, and is not on the front."""
    from beveloid.explore import report
    from beveloid.tooth import report as tooth_report

    plan, cols = face_widths
    values = {k: np.full(plan.count, v) for k, v in plan.base_values().items()}
    values.update(plan.values(0, plan.count))
    for j in range(plan.count):
        found = tooth_report.analyze(Pair.from_spec(rows.design_spec(plan, values, j))).statuses
        geometric = [s for s, _ in found if s in ("undercut", "pointed")]
        assert cols["tooth_status"][j] == " ".join(dict.fromkeys(geometric))
        for s, message in found:
            if s in ("undercut", "pointed"):
                assert message in cols["reason"][j]
    assert cols["status"].tolist() == ["ok", "pointed"]
    assert set(cols["tooth_status"][1].split()) == {"pointed", "undercut"}
    assert cols["reason"][0] == ""
    assert np.isfinite(cols["max_fpd_angle_deg"]).all()  # a flagged design keeps its numbers
    table = dict(cols)
    report.mark_pareto(table, mc=False)
    assert table["pareto"].tolist() == [True, False]


def test_refused_rows_say_why(explored):
    plan, cols, _ = explored
    for j in range(plan.count):
        if cols["status"][j] == "ok":
            assert cols["reason"][j] == ""
        else:
            assert cols["reason"][j], cols["status"][j]

"""Tests for beveloid.spec: loading, validation messages, round-trip, overrides."""

from __future__ import annotations

import copy
import dataclasses
import math
from pathlib import Path

import pytest

from beveloid.spec import (
    KEY_DOCS,
    DesignSpec,
    MemberSpec,
    MisalignmentSpec,
    PairSpec,
    SpecError,
    key_docs_markdown,
    load_spec,
    misalignment_with,
    spec_from_dict,
    spec_to_dict,
)

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

BASE = {
    "pair": {
        "normal_module_mm": 6.0,
        "normal_pressure_angle_deg": 20.0,
        "shaft_angle_deg": 13.0,
        "offset_mm": 229.0,
    },
    "pinion": {
        "teeth": 29,
        "cone_angle_deg": 2.0,
        "helix_angle_deg": 23.0,
        "profile_shift": 0.15,
        "face_width_mm": 50.0,
    },
    "gear": {"teeth": 45, "cone_angle_deg": 0.8, "face_width_mm": 60.0},
    "misalignment": {
        "dx_mm": 0.0,
        "dy_mm": 0.0,
        "dz_mm": 0.0,
        "vertical_deg": 0.0,
        "horizontal_deg": 0.0,
    },
}

_DELETE = object()


def mutated(changes: dict) -> dict:
    """BASE with changes applied; keys are 'section' or 'section.key'; _DELETE removes."""
    data = copy.deepcopy(BASE)
    for dotted, value in changes.items():
        if "." in dotted:
            section, key = dotted.split(".", 1)
            if value is _DELETE:
                del data[section][key]
            else:
                data[section][key] = value
        elif value is _DELETE:
            del data[dotted]
        else:
            data[dotted] = value
    return data


def assert_one_line_error(err: SpecError, *fragments: str) -> str:
    msg = str(err)
    assert "\n" not in msg and "\r" not in msg, msg
    for fragment in fragments:
        assert fragment in msg, f"{fragment!r} not in {msg!r}"
    return msg


# (id, changes, dotted key or missing key name, offending value text, word of what is valid)
BAD_CASES = [
    # --- integers
    ("teeth_too_few", {"pinion.teeth": 5}, "pinion.teeth", "= 5:", "integer from 6 to 400"),
    ("teeth_too_many", {"gear.teeth": 401}, "gear.teeth", "401", "integer from 6 to 400"),
    ("teeth_float", {"pinion.teeth": 29.0}, "pinion.teeth", "29.0", "integer"),
    ("teeth_string", {"gear.teeth": "45"}, "gear.teeth", '"45"', "integer"),
    ("teeth_bool", {"gear.teeth": True}, "gear.teeth", "true", "integer"),
    ("teeth_huge_int", {"gear.teeth": 10**400}, "gear.teeth", "...", "integer from 6 to 400"),
    ("teeth_list", {"pinion.teeth": [29]}, "pinion.teeth", "[29]", "integer"),
    ("teeth_none", {"pinion.teeth": None}, "pinion.teeth", "None", "integer"),
    # --- pair
    ("module_negative", {"pair.normal_module_mm": -1.0}, "pair.normal_module_mm", "-1.0", "from 0.001 to 100"),
    ("module_zero", {"pair.normal_module_mm": 0}, "pair.normal_module_mm", "= 0:", "from 0.001 to 100"),
    # a module whose square underflows (found by the fuzz test's rotating seed: warnings, garbage)
    ("module_subnormal", {"pair.normal_module_mm": 2.75e-264}, "pair.normal_module_mm", "2.75e-264",
     "from 0.001 to 100"),
    ("module_huge", {"pair.normal_module_mm": 101.0}, "pair.normal_module_mm", "101.0", "from 0.001 to 100"),
    ("module_string", {"pair.normal_module_mm": "6"}, "pair.normal_module_mm", '"6"', "number"),
    ("module_bool", {"pair.normal_module_mm": True}, "pair.normal_module_mm", "true", "number"),
    ("pressure_low", {"pair.normal_pressure_angle_deg": 9.9}, "pair.normal_pressure_angle_deg", "9.9", "from 10 to 35"),
    ("pressure_high", {"pair.normal_pressure_angle_deg": 35.5}, "pair.normal_pressure_angle_deg", "35.5", "from 10 to 35"),
    ("shaft_zero", {"pair.shaft_angle_deg": 0.0}, "pair.shaft_angle_deg", "0.0", "> 0"),
    ("shaft_ninety", {"pair.shaft_angle_deg": 90}, "pair.shaft_angle_deg", "90", "< 90"),
    ("offset_nan", {"pair.offset_mm": math.nan}, "pair.offset_mm", "nan", "<= 1000000 (mm)"),
    ("offset_inf", {"pair.offset_mm": math.inf}, "pair.offset_mm", "inf", "<= 1000000 (mm)"),
    ("offset_negative", {"pair.offset_mm": -229}, "pair.offset_mm", "-229", "> 0"),
    ("offset_overflow_int", {"pair.offset_mm": 10**400}, "pair.offset_mm", "...", "<= 1000000 (mm)"),
    # --- members
    ("cone_high", {"pinion.cone_angle_deg": 15.5}, "pinion.cone_angle_deg", "15.5", "from -15 to 15"),
    ("cone_low", {"gear.cone_angle_deg": -16}, "gear.cone_angle_deg", "-16", "from -15 to 15"),
    ("cone_zero", {"pinion.cone_angle_deg": 0}, "pinion.cone_angle_deg", "0", "a non-zero number from -15 to 15"),
    ("helix_60", {"pinion.helix_angle_deg": 60.0}, "pinion.helix_angle_deg", "60.0", "< 60"),
    ("helix_minus_60", {"pinion.helix_angle_deg": -60.0}, "pinion.helix_angle_deg", "-60.0", "> -60"),
    ("shift_high", {"pinion.profile_shift": 1.6}, "pinion.profile_shift", "1.6", "from -1.5 to 1.5"),
    ("shift_string", {"pinion.profile_shift": "0.15"}, "pinion.profile_shift", '"0.15"', "number"),
    ("face_zero", {"pinion.face_width_mm": 0.0}, "pinion.face_width_mm", "0.0", "from 0.001 to 1000"),
    ("face_subnormal", {"pinion.face_width_mm": 5e-324}, "pinion.face_width_mm", "5e-324", "from 0.001 to 1000"),
    ("face_huge", {"gear.face_width_mm": 1001.0}, "gear.face_width_mm", "1001.0", "from 0.001 to 1000"),
    ("addendum_low", {"pinion.addendum_coefficient": 0.2}, "pinion.addendum_coefficient", "0.2", "from 0.3 to 2"),
    ("addendum_high", {"gear.addendum_coefficient": 2.1}, "gear.addendum_coefficient", "2.1", "from 0.3 to 2"),
    ("cutter_low", {"pinion.cutter_addendum_coefficient": 0.4}, "pinion.cutter_addendum_coefficient", "0.4", "from 0.5 to 2.5"),
    ("cutter_high", {"gear.cutter_addendum_coefficient": 2.6}, "gear.cutter_addendum_coefficient", "2.6", "from 0.5 to 2.5"),
    ("clearance_pinion_equal", {"pinion.cutter_addendum_coefficient": 1.0}, "pinion.cutter_addendum_coefficient", "1.0", "exceed gear.addendum_coefficient"),
    ("clearance_gear_tip_high", {"gear.addendum_coefficient": 1.3}, "pinion.cutter_addendum_coefficient", "1.25", "exceed gear.addendum_coefficient = 1.3"),
    ("clearance_gear_cutter", {"gear.cutter_addendum_coefficient": 1.1, "pinion.addendum_coefficient": 1.2}, "gear.cutter_addendum_coefficient", "1.1", "exceed pinion.addendum_coefficient"),
    # a rack tooth deeper than pi / (4 tan alpha) module is pointed: 1.122 at 35 deg, 1.25 just fits at 32 deg
    ("pointed_rack_35deg", {"pair.normal_pressure_angle_deg": 35.0}, "pinion.cutter_addendum_coefficient", "1.25",
     "at most 1.122 at pair.normal_pressure_angle_deg = 35.0"),
    ("pointed_rack_gear", {"pair.normal_pressure_angle_deg": 32.2, "pinion.cutter_addendum_coefficient": 1.2},
     "gear.cutter_addendum_coefficient", "1.25", "pointed"),
    ("ref_offset_beyond_face", {"pinion.reference_section_offset_mm": 60.0}, "pinion.reference_section_offset_mm", "60.0", "pinion.face_width_mm = 50.0"),
    ("ref_offset_negative_beyond", {"gear.reference_section_offset_mm": -61}, "gear.reference_section_offset_mm", "-61", "|value| <="),
    ("ref_offset_nan", {"gear.reference_section_offset_mm": math.nan}, "gear.reference_section_offset_mm", "nan", "<= gear.face_width_mm"),
    # --- misalignment
    ("dx_high", {"misalignment.dx_mm": 10.5}, "misalignment.dx_mm", "10.5", "from -10 to 10"),
    ("dy_low", {"misalignment.dy_mm": -11}, "misalignment.dy_mm", "-11", "from -10 to 10"),
    ("dz_inf", {"misalignment.dz_mm": -math.inf}, "misalignment.dz_mm", "-inf", "from -10 to 10"),
    ("vertical_high", {"misalignment.vertical_deg": 5.1}, "misalignment.vertical_deg", "5.1", "from -5 to 5"),
    ("horizontal_string", {"misalignment.horizontal_deg": "0"}, "misalignment.horizontal_deg", '"0"', "number"),
    ("horizontal_nan", {"misalignment.horizontal_deg": math.nan}, "misalignment.horizontal_deg", "nan", "from -5 to 5"),
    ("misalignment_not_table", {"misalignment": 0.1}, "misalignment", "0.1", "table"),
    # --- design results given for the gear
    ("gear_helix_given", {"gear.helix_angle_deg": 20.0}, "gear.helix_angle_deg", "20.0", "result of the direct design; remove it"),
    ("gear_shift_given", {"gear.profile_shift": 0.1}, "gear.profile_shift", "0.1", "remove it"),
    # --- unknown keys / sections
    ("unknown_key_typo", {"gear.helix_angel_deg": 20.0}, "gear.helix_angel_deg", "unknown key", "did you mean helix_angle_deg?"),
    ("unknown_key_tooth", {"pinion.tooth": 29}, "pinion.tooth", "unknown key", "did you mean teeth?"),
    ("unknown_key_dx", {"misalignment.dx": 1.0}, "misalignment.dx", "unknown key", "valid keys are: dx_mm"),
    ("unknown_key_no_hint", {"pair.colour": "red"}, "pair.colour", "unknown key", "valid keys are: normal_module_mm"),
    ("unknown_section", {"misalignement": {}}, "misalignement", "unknown section", "did you mean misalignment?"),
    ("unknown_top_scalar", {"title": "x"}, "title", "unknown top-level key", "[pair]"),
    # --- missing keys / sections
    ("missing_offset", {"pair.offset_mm": _DELETE}, "pair", "'offset_mm'", "offset between the crossed axes"),
    ("missing_pinion_helix", {"pinion.helix_angle_deg": _DELETE}, "pinion", "'helix_angle_deg'", "missing required key"),
    ("missing_pinion_shift", {"pinion.profile_shift": _DELETE}, "pinion", "'profile_shift'", "profile-shift"),
    ("missing_gear_teeth", {"gear.teeth": _DELETE}, "gear", "'teeth'", "number of teeth"),
    ("missing_gear_face", {"gear.face_width_mm": _DELETE}, "gear", "'face_width_mm'", "face width"),
    ("missing_gear_section", {"gear": _DELETE}, "gear", "[gear]", "needs keys: teeth"),
    ("missing_pair_section", {"pair": _DELETE}, "pair", "[pair]", "needs keys: normal_module_mm"),
    ("pair_not_table", {"pair": 5}, "pair", "= 5:", "must be a table"),
]


def test_enough_bad_cases():
    assert len(BAD_CASES) >= 35
    assert len({case[0] for case in BAD_CASES}) == len(BAD_CASES)


@pytest.mark.parametrize(
    "changes, key, value_text, valid_word",
    [case[1:] for case in BAD_CASES],
    ids=[case[0] for case in BAD_CASES],
)
def test_bad_input(changes, key, value_text, valid_word):
    with pytest.raises(SpecError) as info:
        spec_from_dict(mutated(changes))
    msg = assert_one_line_error(info.value, key, value_text, valid_word)
    assert msg.startswith(key), msg  # no source prefix for plain dicts
    assert isinstance(info.value, ValueError)


def test_exact_message_formats():
    with pytest.raises(SpecError, match=r"^pinion\.teeth = 5: must be an integer from 6 to 400$"):
        spec_from_dict(mutated({"pinion.teeth": 5}))
    with pytest.raises(SpecError) as info:
        spec_from_dict(mutated({"pair.offset_mm": _DELETE}))
    assert str(info.value) == "pair: missing required key 'offset_mm' (offset between the crossed axes, mm)"
    assert info.value.key == "pair.offset_mm"
    with pytest.raises(SpecError) as info:
        spec_from_dict(mutated({"gear.helix_angle_deg": 20.0}))
    assert str(info.value).endswith("gear.helix_angle_deg is a result of the direct design; remove it")
    with pytest.raises(SpecError, match=r"write 29, not 29\.0"):
        spec_from_dict(mutated({"pinion.teeth": 29.0}))


def test_top_level_not_a_table():
    with pytest.raises(SpecError) as info:
        spec_from_dict([1, 2])  # type: ignore[arg-type]
    assert_one_line_error(info.value, "[1, 2]", "must be a table", "[pair]")


def test_source_prefix_for_dicts_with_source():
    with pytest.raises(SpecError) as info:
        spec_from_dict(mutated({"pinion.teeth": 5}), source="my.toml")
    assert str(info.value) == "my.toml: pinion.teeth = 5: must be an integer from 6 to 400"
    assert info.value.detail == "pinion.teeth = 5: must be an integer from 6 to 400"
    assert info.value.source == "my.toml"


def test_long_string_value_stays_one_line():
    with pytest.raises(SpecError) as info:
        spec_from_dict(mutated({"pair.offset_mm": "a\nb" * 50}))
    msg = assert_one_line_error(info.value, "pair.offset_mm", "number")
    assert len(msg) < 200


# ---------------------------------------------------------------------- files


BAD_FILES = [
    # (id, text in case1.toml, replacement, expected message after the path prefix)
    ("teeth", "teeth = 29 ", "teeth = 5 ", "pinion.teeth = 5: must be an integer from 6 to 400"),
    ("float_teeth", "teeth = 29 ", "teeth = 29.0 ", "pinion.teeth = 29.0: must be an integer"),
    ("bool", "profile_shift = 0.15", "profile_shift = true", "pinion.profile_shift = true: must be a number"),
    ("nan", "profile_shift = 0.15", "profile_shift = nan", "pinion.profile_shift = nan: must be a number"),
    ("typo", "helix_angle_deg = 23.0", "helix_angel_deg = 23.0", "pinion.helix_angel_deg: unknown key"),
    ("gear_helix", "face_width_mm = 60.0", "face_width_mm = 60.0\nhelix_angle_deg = -20.0",
     "gear.helix_angle_deg = -20.0: gear.helix_angle_deg is a result of the direct design; remove it"),
    ("section_typo", "[misalignment]", "[misalignement]", "misalignement: unknown section"),
]


@pytest.mark.parametrize("old, new, expected", [c[1:] for c in BAD_FILES], ids=[c[0] for c in BAD_FILES])
def test_bad_file_prefixed_with_path(tmp_path, old, new, expected):
    text = (EXAMPLES / "case1.toml").read_text()
    assert old in text
    path = tmp_path / "bad.toml"
    path.write_text(text.replace(old, new, 1))
    with pytest.raises(SpecError) as info:
        load_spec(path)
    msg = assert_one_line_error(info.value, expected)
    assert msg == f"{path}: {expected}" or msg.startswith(f"{path}: {expected}"), msg


def test_toml_syntax_error(tmp_path):
    path = tmp_path / "syntax.toml"
    path.write_text("[pair]\nnormal_module_mm = = 6\n")
    with pytest.raises(SpecError) as info:
        load_spec(str(path))
    msg = assert_one_line_error(info.value, str(path), "TOML syntax error", "line 2")
    assert msg.startswith(str(path))


def test_missing_file(tmp_path):
    path = tmp_path / "nope.toml"
    with pytest.raises(SpecError) as info:
        load_spec(path)
    assert_one_line_error(info.value, str(path), "no such file")


def test_directory_is_not_a_file(tmp_path):
    with pytest.raises(SpecError) as info:
        load_spec(tmp_path)
    assert_one_line_error(info.value, str(tmp_path), "cannot read spec file")


def test_not_utf8(tmp_path):
    path = tmp_path / "latin1.toml"
    path.write_bytes(b"# \xff\xfe\n[pair]\n")
    with pytest.raises(SpecError) as info:
        load_spec(path)
    assert_one_line_error(info.value, str(path), "UTF-8")


def test_file_without_misalignment_uses_defaults(tmp_path):
    text = (EXAMPLES / "case1.toml").read_text()
    text = text.split("[misalignment]")[0]
    path = tmp_path / "nomis.toml"
    path.write_text(text)
    spec = load_spec(path)
    assert spec.misalignment == MisalignmentSpec()
    assert spec.source == str(path)


# ---------------------------------------------------------------------- examples


@pytest.mark.parametrize(
    "name, cone, helix, shift",
    [("case1.toml", 2.0, 23.0, 0.15), ("case2.toml", 1.0, 20.0, 0.16)],
)
def test_examples_load_and_round_trip(name, cone, helix, shift):
    spec = load_spec(EXAMPLES / name)
    assert spec.pair == PairSpec(6.0, 20.0, 13.0, 229.0)
    assert spec.pinion == MemberSpec(
        teeth=29, cone_angle_deg=cone, face_width_mm=50.0, helix_angle_deg=helix, profile_shift=shift
    )
    assert spec.gear == MemberSpec(teeth=45, cone_angle_deg=0.8, face_width_mm=60.0)
    assert spec.misalignment == MisalignmentSpec()
    assert spec.source.endswith(name)
    assert isinstance(spec.pinion.teeth, int)

    data = spec_to_dict(spec)
    assert "helix_angle_deg" not in data["gear"] and "profile_shift" not in data["gear"]
    again = spec_from_dict(data)
    assert again == spec
    assert spec_to_dict(again) == data
    assert spec_from_dict(copy.deepcopy(data), source=spec.source).source == spec.source


def test_defaults_apply():
    spec = spec_from_dict(mutated({"misalignment": _DELETE}))
    for member in (spec.pinion, spec.gear):
        assert member.addendum_coefficient == 1.0
        assert member.cutter_addendum_coefficient == 1.25
        assert member.reference_section_offset_mm == 0.0
    assert spec.gear.helix_angle_deg is None and spec.gear.profile_shift is None
    assert spec.misalignment == MisalignmentSpec(0.0, 0.0, 0.0, 0.0, 0.0)
    assert spec.source == "<dict>"


def test_ints_become_floats_and_optional_keys_accepted():
    spec = spec_from_dict(
        mutated(
            {
                "pair.offset_mm": 229,
                "pinion.addendum_coefficient": 0.8,
                "pinion.cutter_addendum_coefficient": 1.4,
                "pinion.reference_section_offset_mm": -50,
                "gear.cone_angle_deg": -1,
                "misalignment.vertical_deg": -5,
            }
        )
    )
    assert spec.pair.offset_mm == 229.0 and isinstance(spec.pair.offset_mm, float)
    assert spec.pinion.reference_section_offset_mm == -50.0
    assert spec.gear.cone_angle_deg == -1.0 and isinstance(spec.gear.cone_angle_deg, float)
    assert spec.misalignment.vertical_deg == -5.0


def test_gear_results_as_none_are_accepted():
    data = mutated({})
    data["gear"] = dataclasses.asdict(MemberSpec(teeth=45, cone_angle_deg=0.8, face_width_mm=60.0))
    del data["gear"]["surface_options"]  # the model's own keys go in the section itself
    assert spec_from_dict(data).gear.helix_angle_deg is None


def test_spec_is_frozen_and_source_not_compared():
    a = spec_from_dict(BASE)
    b = spec_from_dict(BASE, source="x.toml")
    assert a == b and hash(a) == hash(b)
    with pytest.raises(dataclasses.FrozenInstanceError):
        a.pair.offset_mm = 1.0  # type: ignore[misc]
    assert isinstance(a, DesignSpec)


# ---------------------------------------------------------------------- misalignment_with


def test_misalignment_with_overrides():
    spec = load_spec(EXAMPLES / "case1.toml")
    moved = misalignment_with(spec, dx_mm=0.1, vertical_deg=-0.05, dy_mm=None)
    assert moved.misalignment == MisalignmentSpec(dx_mm=0.1, vertical_deg=-0.05)
    assert moved.pair == spec.pair and moved.pinion == spec.pinion and moved.gear == spec.gear
    assert moved.source == spec.source
    assert spec.misalignment == MisalignmentSpec()  # original untouched
    again = misalignment_with(moved, dz_mm=2)
    assert again.misalignment == MisalignmentSpec(dx_mm=0.1, dz_mm=2.0, vertical_deg=-0.05)
    assert misalignment_with(spec) == spec


@pytest.mark.parametrize(
    "overrides, fragments",
    [
        ({"dx_mm": 20.0}, ("misalignment.dx_mm = 20.0", "from -10 to 10")),
        ({"horizontal_deg": math.nan}, ("misalignment.horizontal_deg = nan", "from -5 to 5")),
        ({"vertical_deg": True}, ("misalignment.vertical_deg = true", "number")),
        ({"dx": 0.1}, ("misalignment.dx: unknown key", "did you mean dx_mm?")),
    ],
)
def test_misalignment_with_validates(overrides, fragments):
    spec = load_spec(EXAMPLES / "case1.toml")
    with pytest.raises(SpecError) as info:
        misalignment_with(spec, **overrides)
    msg = assert_one_line_error(info.value, *fragments)
    assert msg.startswith("misalignment."), msg


# ---------------------------------------------------------------------- docs table


def test_key_docs_cover_dataclass_fields():
    classes = {"pair": PairSpec, "pinion": MemberSpec, "gear": MemberSpec, "misalignment": MisalignmentSpec}
    for section, cls in classes.items():
        # a tooth-surface model's own keys are gathered in MemberSpec.surface_options
        keys = {k for k, d in KEY_DOCS[section].items() if d.model is None}
        model_keys = {k for k, d in KEY_DOCS[section].items() if d.model is not None}
        fields = {f.name for f in dataclasses.fields(cls)}
        assert keys == fields - {"surface_options"}
        assert not model_keys or "surface_options" in fields
    assert KEY_DOCS["gear"]["helix_angle_deg"].requirement == "result"
    assert KEY_DOCS["pinion"]["helix_angle_deg"].requirement == "required"


def test_key_docs_markdown_has_row_per_key():
    table = key_docs_markdown()
    rows = table.splitlines()
    assert len(rows) == 2 + sum(len(d) for d in KEY_DOCS.values())
    assert all(row.startswith("|") and row.endswith("|") for row in rows)
    assert "`pinion.teeth`" in table and "an integer from 6 to 400" in table


def test_a_key_without_its_dataclass_field_is_refused(monkeypatch):
    """Adding a key is a KeyDoc plus a field: the package names the one that is missing."""
    from beveloid.spec import KeyDoc
    from beveloid.spec.validate import check_fields_match_keys

    check_fields_match_keys()  # the shipped tables agree
    monkeypatch.setitem(KEY_DOCS["pair"], "backlash_mm", KeyDoc("test", "mm", lo=0.0, hi=1.0,
                                                               requirement="optional", default=0.0))
    with pytest.raises(RuntimeError, match=r"\['backlash_mm'\]"):
        check_fields_match_keys()


def test_a_default_that_differs_from_the_field_is_refused(monkeypatch):
    import dataclasses

    from beveloid.spec.validate import check_fields_match_keys

    doc = KEY_DOCS["pinion"]["addendum_coefficient"]
    monkeypatch.setitem(KEY_DOCS["pinion"], "addendum_coefficient", dataclasses.replace(doc, default=1.1))
    with pytest.raises(RuntimeError, match="addendum_coefficient"):
        check_fields_match_keys()


def test_the_schema_says_no_default_where_a_key_has_none():
    """`beveloid example --schema` wrote "(default )" for keys whose default is None (the roughness keys)."""
    from beveloid.spec.schema import key_schema_text

    text = key_schema_text()
    assert "(default )" not in text
    assert "roughness_ra_um: optional (no default)" in text

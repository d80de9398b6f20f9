"""Issue 14: reliability and first-use defects.  One test (or more) per item; the fuzz test is
in test_fuzz_cli.py.  CLI tests call ``beveloid.cli.main`` in-process."""
from __future__ import annotations

import copy
import dataclasses
import json
import os
import re
import time
import warnings
from pathlib import Path

import numpy as np
import pytest

from beveloid import cli
from beveloid.design import DesignError, design, pitch_point_margins
from beveloid.pair import Pair
from beveloid.spec import (
    MAX_SPEC_BYTES,
    SpecError,
    load_spec,
    spec_from_dict,
    spec_to_dict,
)

REPO = Path(__file__).resolve().parents[2]
C1 = str(REPO / "examples" / "case1.toml")
CASE1_TEXT = (REPO / "examples" / "case1.toml").read_text(encoding="utf-8")


def run_cli(capsys, argv):
    """(exit status, stdout, stderr) of an in-process CLI call."""
    rc = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return rc, out, err


def assert_one_line_exit_2(rc, err, *fragments):
    assert rc == 2, err
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("beveloid"), err
    assert "Traceback" not in err
    for f in fragments:
        assert f in lines[0], (f, lines[0])
    return lines[0]


def case1_with(tmp_path, name="spec.toml", **replace):
    """case1.toml with whole lines 'key = ...' replaced (first occurrence)."""
    text = CASE1_TEXT
    for key, value in replace.items():
        text, n = re.subn(rf"^{key} = [^\n#]*", f"{key} = {value}", text, count=1, flags=re.M)
        assert n == 1, key
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


# ---------------------------------------------------------------------------------------------
# 8: infeasible designs are rejected by design(), with key, value and a direction
# ---------------------------------------------------------------------------------------------


def test_pitch_point_below_the_active_profile_is_rejected(tmp_path):
    path = case1_with(tmp_path, offset_mm="1.0")
    with pytest.raises(DesignError) as info:
        design(load_spec(path))
    msg = str(info.value)
    assert "\n" not in msg
    assert "pair.offset_mm = 1.0" in msg and "alpha_nw = 4.2381 deg" in msg
    assert "below the start of the active profile" in msg and "increase pair.offset_mm" in msg
    assert "pair.offset_mm" in info.value.keys


def test_pitch_point_above_the_tip_is_rejected():
    d = spec_to_dict(load_spec(C1))
    d["pinion"]["profile_shift"] = -1.2
    with pytest.raises(DesignError, match=r"above the tip \(tip circle [\d.]+ mm\) of the pinion teeth.*"
                                          r"reduce pair\.offset_mm"):
        design(spec_from_dict(d))


def test_feasibility_check_agrees_with_the_tca_boundaries(monkeypatch):
    """The design's pitch-point check (closed form) and the TCA's flank boundaries (generated surfaces)
    agree on whether the aligned contact at P is on both members' flanks, on random designs."""
    from beveloid import tca

    import beveloid.design.checks as dmod

    real_check = dmod.check_pitch_point
    monkeypatch.setattr(dmod, "check_pitch_point", lambda *a: None)
    rng = np.random.default_rng(5)
    base = spec_to_dict(load_spec(C1))
    seen = {True: 0, False: 0}
    for _ in range(120):
        d = copy.deepcopy(base)
        d["pair"]["offset_mm"] = float(rng.uniform(1, 400))
        d["pinion"]["profile_shift"] = float(rng.uniform(-1, 1))
        d["pinion"]["teeth"] = int(rng.integers(10, 60))
        d["gear"]["teeth"] = int(rng.integers(10, 80))
        d["pinion"]["reference_section_offset_mm"] = float(rng.uniform(-20, 20))
        try:
            r = design(spec_from_dict(d))
        except DesignError:
            continue
        on_profile = all(form <= r_w <= tip for m in (r.pinion, r.gear)
                         for form, tip, r_w in pitch_point_margins(m).values())
        try:
            for m in (r.pinion, r.gear):
                real_check(r.spec, m, r.working_normal_pressure_angle)
            accepted = True
        except DesignError:
            accepted = False
        assert accepted == on_profile
        geom = tca.PairGeometry.from_design(r)
        margins = [float(tca.boundary_margins(geom, fl, tca.reference_contact(geom, fl).x[None])[0][0])
                   for fl in tca.FLANKS]
        assert (min(margins) >= -1e-6) == accepted, (margins, accepted)
        seen[accepted] += 1
    assert seen[True] >= 10 and seen[False] >= 10, seen


def test_sweep_and_tca_on_the_issue_example_exit_2(capsys, tmp_path):
    path = case1_with(tmp_path, offset_mm="1.0")
    for argv in (["design", path], ["tca", path, "--positions", "5"],
                 ["sweep", path, "--samples", "2", "--positions", "3"]):
        rc, _, err = run_cli(capsys, argv)
        assert_one_line_exit_2(rc, err, "pair.offset_mm = 1.0", "pitch point P")


# ---------------------------------------------------------------------------------------------
# 13: huge numbers: no warning, a true message
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("value", ["1e300", "1.7e308", "1000000.5"])
def test_huge_offset_is_a_range_error_without_warnings(capsys, tmp_path, value):
    path = case1_with(tmp_path, offset_mm=value)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # any RuntimeWarning fails the test
        rc, _, err = run_cli(capsys, ["design", path])
    assert_one_line_exit_2(rc, err, "pair.offset_mm = ", "must be a number > 0 and <= 1000000 (mm)")


def test_offset_too_large_quotes_the_true_reachable_range():
    """Near the new bound the message's E range comes from Eq 17 itself, not from E(alpha) - E + E."""
    d = spec_to_dict(load_spec(C1))
    d["pair"]["offset_mm"] = 999_999.0
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(DesignError) as info:
            design(spec_from_dict(d))
    m = re.search(r"Eq 17 gives E from ([\d.e+-]+) to ([\d.e+-]+) mm", str(info.value))
    assert m, str(info.value)
    lo, hi = float(m.group(1)), float(m.group(2))
    assert 0 <= lo < hi and hi == pytest.approx(545.767, abs=1e-3), (lo, hi)  # not "from 0 to 0"
    assert f"at most {m.group(2)} mm" in str(info.value)


# ---------------------------------------------------------------------------------------------
# 14: only regular files, bounded read
# ---------------------------------------------------------------------------------------------


def test_dev_zero_and_fifo_are_refused_quickly(capsys, tmp_path):
    fifo = tmp_path / "pipe.toml"
    os.mkfifo(fifo)
    for target, kind in (("/dev/zero", "a device"), (fifo, "a FIFO"), (tmp_path, "a folder")):
        t0 = time.perf_counter()
        rc, _, err = run_cli(capsys, ["design", target])
        assert time.perf_counter() - t0 < 5
        assert_one_line_exit_2(rc, err, str(target), f"it is {kind}", "regular TOML file")


def test_oversized_file_is_refused(capsys, tmp_path):
    path = tmp_path / "big.toml"
    path.write_bytes(CASE1_TEXT.encode() + b"#" * (MAX_SPEC_BYTES + 10))
    rc, _, err = run_cli(capsys, ["tca", path])
    assert_one_line_exit_2(rc, err, f"more than the {MAX_SPEC_BYTES} bytes")


# ---------------------------------------------------------------------------------------------
# 16: smaller ones
# ---------------------------------------------------------------------------------------------


def test_utf8_bom_is_accepted(tmp_path):
    path = tmp_path / "bom.toml"
    path.write_bytes(b"\xef\xbb\xbf" + CASE1_TEXT.encode())
    assert load_spec(path) == load_spec(C1)


def test_control_characters_in_keys_are_escaped(capsys, tmp_path):
    path = tmp_path / "nul.toml"
    path.write_text(CASE1_TEXT.replace("teeth = 29 ", '"te\\u0000e\\u001b[31mth" = 29 ', 1), encoding="utf-8")
    rc, _, err = run_cli(capsys, ["design", path])
    line = assert_one_line_exit_2(rc, err, r"pinion.te\x00e\x1b[31mth: unknown key", "did you mean teeth?")
    assert line.isprintable()


def test_dates_are_shown_as_dates(tmp_path):
    path = case1_with(tmp_path, teeth="1979-05-27")
    with pytest.raises(SpecError) as info:
        load_spec(path)
    assert "pinion.teeth = 1979-05-27 (a date): must be an integer from 6 to 400" in str(info.value)
    assert "datetime" not in str(info.value)


@pytest.mark.parametrize("line, words", [
    ("title = 1", ["title = 1: unknown top-level key", "[pair], [pinion]"]),
    ("teeth = 29", ["teeth = 29: unknown top-level key", "teeth belongs in [pinion] or [gear]"]),
    ("[extra]", ["extra: unknown section", "valid sections are: pair"]),
])
def test_top_level_keys_are_not_called_sections(tmp_path, line, words):
    path = tmp_path / "top.toml"
    path.write_text(line + "\n" + CASE1_TEXT if not line.startswith("[") else CASE1_TEXT + "\n" + line + "\n")
    with pytest.raises(SpecError) as info:
        load_spec(path)
    for w in words:
        assert w in str(info.value)


# ---------------------------------------------------------------------------------------------
# 10, 11: every output target is checked before any computation
# ---------------------------------------------------------------------------------------------


def _targets(tmp_path):
    folder = tmp_path / "existing_folder.png"
    folder.mkdir()
    ro_file = tmp_path / "readonly.png"
    ro_file.write_bytes(b"")
    ro_file.chmod(0o444)
    ro_dir = tmp_path / "ro_dir"
    ro_dir.mkdir()
    ro_dir.chmod(0o555)
    a_file = tmp_path / "a_file"
    a_file.write_text("x")
    return folder, ro_file, ro_dir, a_file


@pytest.fixture
def targets(tmp_path):
    t = _targets(tmp_path)
    yield t
    t[2].chmod(0o755)


def _no_compute(monkeypatch):
    """Any design or TCA during the call fails the test: the target must be refused first."""
    def boom(*a, **k):
        raise AssertionError("computed before checking the output target")
    monkeypatch.setattr("beveloid.design.design", boom)
    monkeypatch.setattr("beveloid.studies.paper.run", boom)


ROOT = os.geteuid() == 0  # root may write anywhere: the permission cases only apply to other users


def test_plot_targets_are_refused_before_computing(capsys, monkeypatch, tmp_path, targets):
    folder, ro_file, ro_dir, a_file = targets
    _no_compute(monkeypatch)
    cases = [
        (folder, "is a folder"),
        *([] if ROOT else [(ro_file, "the file exists and is not writable"), (ro_dir / "x.png", "is not writable")]),
        (tmp_path / ("n" * 300 + ".png"), "more than the 255"),
        ("", "an empty name"),
        (a_file / "x.png", "does not exist"),
        (tmp_path / "plot.svg", "ending in .png"),
    ]
    for target, words in cases:
        for argv in (["tca", C1, "--positions", "3"], ["ltca", C1, "--torque-nm", "10", "--positions", "3"],
                     ["design", C1]):
            rc, _, err = run_cli(capsys, [*argv, "--plot", target])
            assert_one_line_exit_2(rc, err, "--plot = ", words)


def test_out_targets_are_refused_before_computing(capsys, monkeypatch, tmp_path, targets):
    folder, ro_file, ro_dir, a_file = targets
    _no_compute(monkeypatch)
    cases = [
        ("", "an empty name"),  # item 11: used to write 23 files into the current folder
        ("   ", "an empty name"),
        (a_file, "exists and is not a folder"),
        *([] if ROOT else [(ro_dir, "is not writable"), (ro_dir / "new" / "deeper", "does not exist")]),
        (tmp_path / ("d" * 256), "more than the 255"),
    ]
    for target, words in cases:
        rc, _, err = run_cli(capsys, ["paper", "--out", target])
        assert_one_line_exit_2(rc, err, "--out = ", words)


def test_every_output_flag_of_every_command_is_checked():
    """The flags that name an output (--plot, --out) are exactly the ones this module checks; a new one
    must be added to the checks (and to the tests above)."""
    parser = cli.build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    outputs = {(name, opt) for name, p in sub.choices.items() for a in p._actions for opt in a.option_strings
               if opt in ("--plot", "--out", "--output", "-o", "--png", "--csv")}
    assert outputs == {("tca", "--plot"), ("ltca", "--plot"), ("ltca", "--csv"), ("paper", "--out"), ("export", "--out"),
                       ("explore", "--out"), ("design", "--plot"), ("rating", "--plot"), ("derive", "--out"),
                       ("fe-check", "--out"), ("optimize", "--out")}
    # export: tests/export, explore: tests/explore, rating: tests/rating, derive: tests/cli/test_cli_outputs.py,
    # fe-check: tests/fecheck, ltca --csv: tests/ltca/test_ltca_batch.py, optimize: tests/optimize
    # (both through beveloid.outputs.check_output_dir, the one output rule)


# ---------------------------------------------------------------------------------------------
# 3, 4, 9, 12: sweep
# ---------------------------------------------------------------------------------------------

WIDE = ["--dx-max", "9.99", "--dy-max", "9.99", "--dz-max", "9.99", "--vertical-max", "4.99",
        "--horizontal-max", "4.99"]


def test_sweep_text_gives_counts_per_status_and_sets_behind_each_statistic(capsys):
    argv = ["sweep", C1, "--samples", "400", "--positions", "5", *WIDE]
    rc, text, _ = run_cli(capsys, argv)
    assert rc == 0
    rc, out, _ = run_cli(capsys, argv + ["--json"])
    o = json.loads(out)
    counts = o["status_counts"]
    assert counts["failed"] > 0 and counts["outside"] > 0  # the wide ranges do produce failures
    for status in ("ok", "edge", "outside", "failed"):
        assert re.search(rf"\b{counts[status]} {status} \(", text), status
    n = o["pinion_path_shift_mm"]["count"]
    assert n == o["sets_with_contact"] < 400
    for name in ("pinion path shift", "gear path shift"):
        assert re.search(rf"{name} .* {n} of 400 sets$", text, flags=re.M), name
    assert 0 < n
    assert re.search(rf"TE peak-to-peak .* {o['te_peak_to_peak_urad']['count']} of 400 sets$", text, flags=re.M)
    assert f"with failed points: {o['sets_with_failed_points']} of 400" in text


def test_sweep_draws_about_the_files_misalignment(capsys, tmp_path):
    path = case1_with(tmp_path, dx_mm="0.02", vertical_deg="-0.004")
    tiny = [f"--{k}-max" for k in ("dx", "dy", "dz", "vertical", "horizontal")]
    tiny = [a for flag in tiny for a in (flag, "0.0001")]
    rc, out, _ = run_cli(capsys, ["sweep", path, "--samples", "20", "--positions", "4", *tiny, "--json"])
    assert rc == 0
    o = json.loads(out)
    assert o["nominal_errors"] == {"dx_mm": 0.02, "dy_mm": 0.0, "dz_mm": 0.0, "vertical_deg": -0.004,
                                   "horizontal_deg": 0.0}
    rc, text, _ = run_cli(capsys, ["sweep", path, "--samples", "20", "--positions", "4"])
    assert "nominal errors (the file's [misalignment]): dx_mm 0.02, dy_mm 0, dz_mm 0, vertical_deg -0.004" in text
    # the sets really lie about the nominal: the mean path shift is the first-order shift of the nominal
    sens = o["sensitivity"]["pinion_axial_shift_mm_per_unit"]
    expect = 0.02 * sens["dx_mm"] - 0.004 * sens["vertical_deg"]
    assert abs(expect) > 0.5
    assert o["pinion_path_shift_mm"]["mean"] == pytest.approx(expect, rel=0.05)
    from beveloid import sweep as sw

    e = sw.draw_errors(500, {"dx_mm": 0.05, "vertical_deg": 0.01}, 0, {"dx_mm": 0.4, "vertical_deg": -0.1})
    assert np.all(np.abs(e[:, 0] - 0.4) <= 0.05) and np.all(np.abs(np.degrees(e[:, 3]) + 0.1) <= 0.01 + 1e-12)
    path = case1_with(tmp_path, "far.toml", dx_mm="0.4")
    rc, _, err = run_cli(capsys, ["sweep", path, "--samples", "2", "--positions", "3", "--dx-max", "9.9"])
    assert_one_line_exit_2(rc, err, "--dx-max = 9.9 with misalignment.dx_mm = 0.4", "<= 10 mm")


def test_help_and_readme_document_the_nominal_errors():
    parser = cli.build_parser()
    sub = next(a for a in parser._actions if a.dest == "command").choices["sweep"]
    assert "[misalignment]" in " ".join(sub.format_help().split())
    commands = (REPO / "docs" / "commands.md").read_text(encoding="utf-8")
    assert "nominal_errors" in commands and "[misalignment]" in commands.split("## sweep")[1].split("## ")[0]


def test_sweep_without_aligned_contact_is_one_line(capsys, monkeypatch, tmp_path):
    """Item 8 now rejects the issue's design in design(); with that check off, the sweep itself must
    still report the flank without contact in one line."""
    monkeypatch.setattr("beveloid.design.checks.check_pitch_point", lambda *a: None)
    path = case1_with(tmp_path, offset_mm="1.0")
    rc, _, err = run_cli(capsys, ["sweep", path, "--samples", "2", "--positions", "3", "--flank", "right"])
    assert_one_line_exit_2(rc, err, "cannot sweep the right flank", "no contact", "beveloid tca")


def test_other_runtime_errors_are_not_swallowed(monkeypatch, tmp_path):
    def cache_error(*a, **k):
        raise RuntimeError("cannot cache function 'x': no locator available")
    monkeypatch.setattr("beveloid.sweep.analyze", cache_error)
    with pytest.raises(RuntimeError, match="cannot cache"):
        cli.main(["sweep", C1, "--samples", "2", "--positions", "3"])


def test_sweep_memory_is_bounded(capsys):
    from beveloid import sweep as sw

    t0 = time.perf_counter()
    rc, _, err = run_cli(capsys, ["sweep", C1, "--samples", "10000000", "--positions", "10000"])
    assert time.perf_counter() - t0 < 2
    assert_one_line_exit_2(rc, err, "100000000000 contact points", f"at most {sw.MAX_CONTACT_POINTS}")
    commands = (REPO / "docs" / "commands.md").read_text(encoding="utf-8")
    assert f"{sw.MAX_CONTACT_POINTS:,}" in commands or str(sw.MAX_CONTACT_POINTS) in commands
    with pytest.raises(ValueError, match="at most"):
        sw.analyze(None, sw.Options(samples=sw.MAX_CONTACT_POINTS, positions=2))


@pytest.mark.parametrize("samples, positions", [(0, 5), (-3, 5), (5, 1), (2.5, 5)])
def test_api_sweep_rejects_bad_sizes_without_numpy_warnings(geom1, samples, positions):
    from beveloid import sweep as sw

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match="must be an integer"):
            sw.analyze(geom1, sw.Options(samples=samples, positions=positions))


# ---------------------------------------------------------------------------------------------
# 17: first use: packaged examples and the key schema
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", ["case1", "case2"])
def test_example_prints_a_spec_that_designs(capsys, monkeypatch, tmp_path, name):
    monkeypatch.chdir(tmp_path)  # no checkout around
    rc, out, err = run_cli(capsys, ["example", name])
    assert rc == 0 and err == ""
    assert out == (REPO / "examples" / f"{name}.toml").read_text(encoding="utf-8")
    (tmp_path / "my.toml").write_text(out, encoding="utf-8")
    rc, out, _ = run_cli(capsys, ["design", "my.toml", "--json"])
    assert rc == 0
    from beveloid.spec import load_example

    assert load_spec(tmp_path / "my.toml") == load_example(name)


def test_schema_lists_every_key(capsys):
    from beveloid.spec import KEY_DOCS

    rc, out, _ = run_cli(capsys, ["example", "--schema"])
    assert rc == 0
    for section, docs in KEY_DOCS.items():
        assert f"[{section}]" in out
        block = out.split(f"[{section}]\n", 1)[1].split("\n\n", 1)[0]
        for key, doc in docs.items():
            line = next(li for li in block.splitlines() if li.startswith(key + ":"))
            assert doc.description in line
            if doc.requirement == "required":
                assert "required" in line and doc.valid_text_in(section) in line
            elif doc.requirement == "optional":
                assert (f"optional (default {doc.default_text})" if doc.default_text else "optional (no default)") in line
            else:
                assert "do not give" in line


@pytest.mark.parametrize("argv, words", [
    (["example"], ["NAME is missing", "case1, case2"]),
    (["example", "case1", "--schema"], ["not both"]),
    (["example", "case9"], ["invalid choice", "case9"]),
])
def test_example_usage_errors_are_one_line(capsys, argv, words):
    rc, _, err = run_cli(capsys, argv)
    assert_one_line_exit_2(rc, err, *words)


# ---------------------------------------------------------------------------------------------
# 7: the design table and the JSON agree on what each number is
# ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("case", ["case1", "case2"])
def test_table_columns_hold_what_the_json_holds(capsys, case):
    path = REPO / "examples" / f"{case}.toml"
    rc, text, _ = run_cli(capsys, ["design", path])
    assert rc == 0
    rc, out, _ = run_cli(capsys, ["design", path, "--json"])
    j = json.loads(out)
    lines = text.splitlines()
    head = [c.strip() for c in lines[1].split("|")]
    assert head == ["Parameter", "Symbol", "Pinion", "Gear", "Pair"]
    cells = {}
    for li in lines[3:]:
        parts = [c.strip() for c in li.split("|")]
        if len(parts) >= 3:
            cells[parts[1]] = parts[2:] + [""] * (5 - len(parts))
    for sym, key in (("ξL", "fpd_angle_left_deg"), ("ξR", "fpd_angle_right_deg")):
        pin, gear, pair = (float(c) for c in cells[sym])
        assert pin == pytest.approx(j["pinion"][key], abs=1e-6)
        assert gear == pytest.approx(j["gear"][key], abs=1e-6)
        assert pair == pytest.approx(j[key], abs=1e-6)
        assert pair == pytest.approx(pin + gear, abs=2e-6)  # Eq 18
    assert float(cells["αnw"][2]) == pytest.approx(j["working_normal_pressure_angle_deg"], abs=1e-6)
    assert cells["αnw"][:2] == ["", ""] and cells["δ"][:2] == ["", ""]
    assert float(cells["E"][2]) == pytest.approx(j["offset_mm"])


# ---------------------------------------------------------------------------------------------
# 5, 6: tca table and figures say what the numbers rest on
# ---------------------------------------------------------------------------------------------


def _table_row(text, flank):
    head = next(li for li in text.splitlines() if li.startswith("flank "))
    row = next(li for li in text.splitlines() if li.startswith(flank + " "))
    return head, row


def test_failed_points_are_not_called_off_the_flank():
    from beveloid import tca
    from beveloid.cli.tca import format_summary

    spec = load_spec(C1)
    res = tca.analyze(Pair.from_spec(spec).geometry, tca.Options(flanks=("right",), positions=5, approach_mm=None))
    fr = res.flanks["right"]
    n = len(fr.status)
    lost = np.full_like(fr.pinion_contact, np.nan)  # as when the solver loses track everywhere
    fr = dataclasses.replace(fr, status=["failed"] * n, pinion_contact=lost, gear_contact=lost)
    res = dataclasses.replace(res, flanks={"right": fr})  # a result is frozen: a new one
    text = format_summary(res, spec)
    _, row = _table_row(text, "right")
    assert "none (not solved)" in row and "off the flank" not in text
    res = dataclasses.replace(res, flanks={"right": dataclasses.replace(fr, status=["outside"] * (n - 2) + ["failed"] * 2)})
    assert f"none ({n - 2} outside, 2 failed)" in _table_row(format_summary(res, spec), "right")[1]


def test_te_from_a_few_positions_carries_a_caveat(capsys):
    """Positions where no pair carries a contact (edge contact now covers what the surface
    contact leaves; here some positions are made contact-free as a failed solve leaves them)."""
    from beveloid import tca
    from beveloid.cli.tca import format_summary

    spec = load_spec(C1)
    res = tca.analyze(Pair.from_spec(spec).geometry, tca.Options(positions=30, approach_mm=None, errors=(1.2, 0, 0, 0, 0)))
    fr = res.flanks["right"]
    pairs = len(fr.status) // 30
    gone = np.zeros((pairs, 30), bool)
    gone[:, :7] = True
    gone = gone.ravel()
    fr = dataclasses.replace(fr, status=["failed" if g else s for g, s in zip(gone, fr.status)],
                             transmission_error=np.where(gone, np.nan, fr.transmission_error))
    res = dataclasses.replace(res, flanks=dict(res.flanks, right=fr))  # a result is frozen: a new one
    text = format_summary(res, spec)
    head, row = _table_row(text, "right")
    assert head.split()[-2:] == ["TE", "points"]
    complete = fr.te_envelope_complete  # the envelope's complete positions (mesh.envelope_complete)
    n = int((complete & ~gone.reshape(pairs, 30)[0]).sum())
    assert 0 < n < int(complete.sum()) <= 30
    assert row.split()[-1] == f"{n}/30"
    assert f"note: right flank: TE peak-to-peak from {n} of 30 positions only" in text
    _, left = _table_row(text, "left")
    n_left = int(res.flanks["left"].te_envelope_complete.sum())
    assert left.split()[-1] == f"{n_left}/30" and "note: left flank: TE peak-to-peak" not in text


def _capture_figures(monkeypatch):
    from beveloid import plots

    figs = []
    monkeypatch.setattr(plots, "_save", lambda fig, *a, **k: figs.append(fig))
    return figs


def test_zero_te_is_said_and_drawn_on_a_sensible_scale(monkeypatch):
    from beveloid import plots, tca

    geom = Pair.from_spec(C1).geometry
    res = tca.analyze(geom, tca.Options(positions=12, approach_mm=None))
    assert 0 < res.flanks["right"].te_peak_to_peak * 1e6 < plots.TE_ZERO_URAD  # round-off, not signal
    figs = _capture_figures(monkeypatch)
    plots.tca_summary(res, geom, "unused.png")
    plots.transmission_error([res], ["aligned"], "right", "unused.png")
    for fig, te_axes in ((figs[0], [row[2] for row in np.reshape(figs[0].axes, (-1, 3))[:2]]), (figs[1], [figs[1].axes[0]])):
        for ax in te_axes:
            lo, hi = ax.get_ylim()
            assert hi - lo == pytest.approx(2 * plots.TE_FLAT_HALF_SPAN_URAD)
            texts = " ".join(t.get_text() for t in ax.texts)
            assert "TE is zero to the solver tolerance" in texts
    legend = [t.get_text() for t in figs[1].axes[0].get_legend().get_texts() if not t.get_text().startswith("faded")]
    assert legend and all(re.search(r"mean [+-][\d.]+ urad, peak-to-peak", t) for t in legend), legend


def test_real_te_is_not_flattened(monkeypatch):
    """A TE above the threshold keeps matplotlib's scale and gets no 'zero' remark."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from beveloid import plots

    fig, ax = plt.subplots()
    ax.plot([0, 1, 2], [0.0, 7.5, 0.0])
    assert plots.te_axis(ax, [0.0, 7.5], [7.5]) is False
    assert ax.get_ylim()[1] > 7 and not ax.texts
    plt.close(fig)


def test_the_status_counts_count_edge_only_where_the_pair_carries():
    """issue 60: the table counted "edge" over pair-positions that carry nothing (197 edge where all 200
    carrying points were ok, on the issue's pair): ok and edge are the carrying ones, idle the others."""
    from beveloid import tca
    from beveloid.cli.tca import format_summary

    spec = load_spec(str(REPO / "tests" / "data" / "issue60_pair.toml"))
    res = tca.analyze(Pair.from_spec(spec).geometry, tca.Options(flanks=("right",), positions=24, approach_mm=None))
    fr = res.flanks["right"]
    st, carrying = np.array(fr.status), np.asarray(fr.active, bool)
    assert ((st == "edge") & ~carrying).sum() > 0  # the idle pairs' edge contacts the old table counted
    head, row = _table_row(format_summary(res, spec), "right")
    counts = dict(zip(head.split()[1:6], (int(v) for v in row.split()[1:6])))
    assert counts == {"ok": int(((st == "ok") & carrying).sum()), "edge": int(((st == "edge") & carrying).sum()),
                      "idle": int((np.isin(st, ["ok", "edge"]) & ~carrying).sum()),
                      "outside": int((st == "outside").sum()), "failed": int((st == "failed").sum())}
    assert counts["ok"] + counts["edge"] == carrying.sum()


def test_the_help_names_the_default_fe_tooth(capsys):
    """issue 60: `beveloid --help` and `ltca --help` called the loaded analysis "half-space + tooth beams"
    while the FE tooth is its default."""
    for argv in (["--help"], ["ltca", "--help"]):
        assert cli.main(argv) == 0
        text = " ".join(capsys.readouterr().out.split())
        assert "half-space + tooth beams" not in text and "half-space + the FE tooth" in text

"""`beveloid tca`, `sweep`, `paper` and `design --json` from the command line (in-process), and
the physics / backend agreement behind them.

Every check is a contract (JSON shape, null policy, exit codes) or a physical property (contact
on the flanks, the aligned pair touching at the pitch point, an axial gear shift being a screw
motion of an involute helicoid, ...); no number is copied from a previous run of the code.
"""
from __future__ import annotations

import csv
import json
import math
import re
import types
from pathlib import Path

import numpy as np
import pytest

from beveloid import cli, sweep, tca
from beveloid.solver import Solver, backends
from beveloid.design import design
from beveloid.spec import load_spec

ROOT = Path(__file__).resolve().parents[2]
CASE1 = ROOT / "examples" / "case1.toml"
CASE2 = ROOT / "examples" / "case2.toml"
STATUSES = {"ok", "edge", "outside", "failed"}
FLANK_ARRAYS = ("pinion_angle_rad", "gear_angle_rad", "transmission_error_rad", "pinion_contact_mm",
                "gear_contact_mm", "status", "contact_boundary", "boundary_margin_mm")
TIMING_KEYS = {"seconds", "seconds_total", "us_per_point", "us_per_point_total"}
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
EDGE_TOL = 1e-8  # mm: an edge contact lies on its boundary (round-off)


# ------------------------------------------------------------------------------------------
# helpers
# ------------------------------------------------------------------------------------------
def _reject_constant(name):
    raise ValueError(f"non-standard JSON constant {name}")


def strict_json(text):
    """json.loads that refuses NaN / Infinity (the output must be strict JSON)."""
    return json.loads(text, parse_constant=_reject_constant)


def run_cli(capsys, argv):
    rc = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return rc, out, err


def run_json(capsys, argv):
    rc, out, err = run_cli(capsys, argv)
    assert rc == 0, err
    assert "Traceback" not in err
    return strict_json(out)  # stdout holds the JSON and nothing else


@pytest.fixture(scope="module")
def geom2(pair2):
    return pair2.geometry


def _is_finite_number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def _is_point(v):
    return isinstance(v, list) and len(v) == 3 and all(_is_finite_number(c) for c in v)


def check_flank_json(fd, geom, n_expected):
    """The per-flank contract of `tca --json` plus 'contact lies on both flanks'."""
    for key in FLANK_ARRAYS:
        assert key in fd, key
        assert isinstance(fd[key], list) and len(fd[key]) == n_expected, key
    counts = dict.fromkeys(STATUSES, 0)
    for i, st in enumerate(fd["status"]):
        assert st in STATUSES, st
        counts[st] += 1
        assert _is_finite_number(fd["pinion_angle_rad"][i])
        if st in ("outside", "failed"):
            for key in ("gear_angle_rad", "transmission_error_rad", "pinion_contact_mm", "gear_contact_mm"):
                assert fd[key][i] is None, (i, st, key, fd[key][i])
            continue
        # ok / edge: a real contact, carried as finite numbers; edge contact names its boundary
        assert (fd["contact_boundary"][i] is None) == (st == "ok"), (i, st, fd["contact_boundary"][i])
        assert _is_finite_number(fd["gear_angle_rad"][i]), (i, st)
        assert _is_finite_number(fd["transmission_error_rad"][i]), (i, st)
        assert _is_point(fd["pinion_contact_mm"][i]), (i, st)
        assert _is_point(fd["gear_contact_mm"][i]), (i, st)
        for member, key in ((geom.pinion, "pinion_contact_mm"), (geom.gear, "gear_contact_mm")):
            x, y, z = fd[key][i]
            r = math.hypot(x, y)
            assert _root_radius(member, z) <= r <= member.tip_radius(z) + EDGE_TOL, (key, i, st, r, z)
            assert abs(z) <= member.face_width_mm / 2 + EDGE_TOL, (key, i, st, z)
    return counts


ELLIPSE_ARRAYS = ("contact_ellipse_semi_axes_mm", "contact_ellipse_major_axis_deg",
                  "contact_ellipse_truncated_length_mm", "contact_ellipse_status")


def check_ellipse_json(fd, n_expected):
    """Contact ellipses: numbers exactly where a point is a contact, a >= b > 0, the truncated
    chord no longer than 2a, the axis angle in (-90, 90]; otherwise null with a status."""
    for key in ELLIPSE_ARRAYS:
        assert isinstance(fd[key], list) and len(fd[key]) == n_expected, key
    for i, st in enumerate(fd["status"]):
        ab, ang, chord = (fd[k][i] for k in ELLIPSE_ARRAYS[:3])
        est = fd["contact_ellipse_status"][i]
        if st in ("outside", "failed"):
            assert (ab, ang, chord, est) == (None, None, None, "no contact"), (i, st)
            continue
        assert est in ("ellipse", "line contact"), (i, est)
        assert _is_finite_number(ang) and -90 < ang <= 90
        assert _is_finite_number(chord) and chord >= 0
        if est == "ellipse":
            a, b = ab
            assert _is_finite_number(a) and _is_finite_number(b) and a >= b > 0
            assert chord <= 2 * a * (1 + 1e-12)
        else:
            assert ab is None


# ------------------------------------------------------------------------------------------
# 1. tca --json contract
# ------------------------------------------------------------------------------------------
MISALIGNED_FLAGS = ["--dx", "0.5", "--dy", "0.5", "--dz", "0.5", "--horizontal", "0.03"]


def _root_radius(m, z):
    """Root cone radius from the blank's definition (cutter addendum below the shifted rack pitch plane)."""
    return m.pitch_radius_mm + (m.rack_shift_mm - m.cutter_addendum_mm) / math.cos(m.cone_angle) + z * math.tan(m.cone_angle)


@pytest.mark.parametrize("case, flags, flanks", [
    (CASE1, [], ("left", "right")),
    (CASE1, MISALIGNED_FLAGS, ("left", "right")),
    (CASE1, ["--flank", "both", "--vertical", "-0.2"], ("left", "right")),
    (CASE2, ["--flank", "right", *MISALIGNED_FLAGS], ("right",)),
    (CASE2, ["--flank", "left"], ("left",)),
], ids=["case1-aligned", "case1-misaligned", "case1-vertical", "case2-right-misaligned", "case2-left"])
def test_tca_json_contract(capsys, case, flags, flanks, geom1, geom2):
    positions, pairs = 11, 3
    data = run_json(capsys, ["tca", case, "--positions", positions, "--json", *flags])
    geom = geom1 if case == CASE1 else geom2
    assert isinstance(data["flanks"], dict)
    assert tuple(data["flanks"]) == flanks
    assert set(data["te_peak_to_peak_urad"]) == set(flanks)
    assert ("backlash_um" in data) == (set(flanks) == {"left", "right"})
    totals = dict.fromkeys(STATUSES, 0)
    for fl in flanks:
        fd = data["flanks"][fl]
        for st, c in check_flank_json(fd, geom, positions * pairs).items():
            totals[st] += c
        assert sorted(set(fd["tooth_pair"])) == [-1, 0, 1]
        check_ellipse_json(fd, positions * pairs)
        ptp = data["te_peak_to_peak_urad"][fl]
        if ptp is not None:
            assert _is_finite_number(ptp) and ptp >= 0
            # consistent with the TE of the points that carry the contact where the envelope is complete
            complete = fd["te_envelope_complete"]
            assert len(complete) == positions and sum(complete) >= 2
            te = [t for i, (t, a) in enumerate(zip(fd["transmission_error_rad"], fd["active"]))
                  if a and t is not None and complete[i % positions]]
            assert te, "a finite TE peak-to-peak needs active points"
            assert abs((max(te) - min(te)) * 1e6 - ptp) <= 1e-5
            # unmodified involute helicoids transmit a constant ratio while the contact stays on the
            # flanks: aligned, the edge contacts of the neighbouring pairs never carry the mesh
            if not flags:
                assert ptp < 1e-3
    if "backlash_um" in data:
        assert data["backlash_um"] is None or _is_finite_number(data["backlash_um"])
    assert data["approach_mm"] == 0.00632
    assert totals["ok"] + totals["edge"] > 0
    if flags:  # misaligned: part of the window leaves the flanks, and those points are null above
        assert totals["outside"] + totals["failed"] + totals["edge"] > 0


def test_tca_aligned_contact_at_pitch_point_and_backlash_free(capsys, geom1):
    """Aligned: pair 0 at the reference pinion angle touches at the designed pitch point
    (working pitch circles, z = 0 in both frames); the Eq 27 design has no backlash."""
    positions = 13  # odd: the middle pinion angle is the reference one
    data = run_json(capsys, ["tca", CASE1, "--positions", positions, "--json"])
    assert data["errors"] == {k: 0.0 for k in ("dx_mm", "dy_mm", "dz_mm", "vertical_deg", "horizontal_deg")}
    assert abs(data["backlash_um"]) < 1e-3
    for fl in ("left", "right"):
        fd = data["flanks"][fl]
        idx = [i for i, k in enumerate(fd["tooth_pair"]) if k == 0]
        mid = idx[len(idx) // 2]
        assert fd["status"][mid] == "ok"
        for member, key in ((geom1.pinion, "pinion_contact_mm"), (geom1.gear, "gear_contact_mm")):
            x, y, z = fd[key][mid]
            assert math.hypot(x, y) == pytest.approx(member.working_pitch_radius_mm, abs=1e-6)
            assert abs(z - member.reference_section_offset_mm) < 1e-6
        assert abs(fd["transmission_error_rad"][mid]) < 1e-9


# ------------------------------------------------------------------------------------------
# 2. flags override the file's [misalignment]
# ------------------------------------------------------------------------------------------
def _with_misalignment(tmp_path, name, table):
    text = CASE1.read_text()
    head, sep, _old = text.partition("[misalignment]")
    assert sep, "examples/case1.toml has a [misalignment] table"
    body = "\n".join(f"{k} = {v!r}" for k, v in table.items())
    path = tmp_path / name
    path.write_text(head + "[misalignment]\n" + body + "\n")
    return path


def test_flags_override_file_misalignment(capsys, tmp_path):
    aligned_file = tmp_path / "aligned.toml"
    aligned_file.write_text(CASE1.read_text().partition("[misalignment]")[0])  # no table at all
    only_dx = _with_misalignment(tmp_path, "dx.toml", {"dx_mm": 0.5})
    several = _with_misalignment(tmp_path, "several.toml",
                                 {"dx_mm": 0.5, "dy_mm": -0.3, "vertical_deg": 0.1, "horizontal_deg": 0.01})
    args = ["--positions", 9, "--json"]

    aligned = run_json(capsys, ["tca", aligned_file, *args])
    from_file = run_json(capsys, ["tca", only_dx, *args])
    assert from_file["errors"]["dx_mm"] == 0.5
    assert from_file["flanks"] != aligned["flanks"]  # the file's error is applied ...
    overridden = run_json(capsys, ["tca", only_dx, "--dx", "0", *args])
    assert overridden["errors"] == aligned["errors"] == {k: 0.0 for k in aligned["errors"]}
    assert overridden["flanks"] == aligned["flanks"]  # ... and --dx 0 takes it back
    assert overridden["te_peak_to_peak_urad"] == aligned["te_peak_to_peak_urad"]
    assert overridden["backlash_um"] == aligned["backlash_um"]

    # every error given in the file, all cancelled by flags
    cancelled = run_json(capsys, ["tca", several, "--dx", "0", "--dy", "0", "--vertical", "0",
                                  "--horizontal", "0", *args])
    assert cancelled["flanks"] == aligned["flanks"]

    # a partial override: the flag wins, the other file values stay
    partial = run_json(capsys, ["tca", several, "--dx", "0.25", "--dz", "0.2", *args])
    e = partial["errors"]
    assert e["dx_mm"] == 0.25 and e["dz_mm"] == 0.2 and e["dy_mm"] == -0.3
    assert e["vertical_deg"] == pytest.approx(0.1, abs=1e-12)
    assert e["horizontal_deg"] == pytest.approx(0.01, abs=1e-12)
    file_only = run_json(capsys, ["tca", several, *args])
    assert file_only["errors"]["dx_mm"] == 0.5 and file_only["errors"]["dz_mm"] == 0.0
    assert partial["flanks"] != file_only["flanks"]

    # the text summary echoes the errors actually used
    rc, out, _ = run_cli(capsys, ["tca", only_dx, "--dx", "0", "--positions", 9])
    assert rc == 0
    assert "dx=0 mm" in out.splitlines()[0]


# ------------------------------------------------------------------------------------------
# 3. bad input: exit 2, one line, no traceback
# ------------------------------------------------------------------------------------------
@pytest.fixture
def bad_files(tmp_path):
    case1 = CASE1.read_text()
    files = {
        "missing": tmp_path / "no_such_file.toml",
        "badtoml": tmp_path / "bad_syntax.toml",
        "unknown": tmp_path / "unknown_key.toml",
        "badvalue": tmp_path / "bad_value.toml",
        "infeasible": tmp_path / "infeasible.toml",
        "case1": CASE1,
        "dir": tmp_path,
        "blocked_out": tmp_path / "a_file" / "sub",
    }
    files["badtoml"].write_text("[pair\nnormal_module_mm = 6\n")
    files["unknown"].write_text(case1.replace("\nteeth = 45", "\nfoo_mm = 1.0\nteeth = 45", 1))
    files["badvalue"].write_text(case1.replace("teeth = 29", "teeth = 5", 1))
    infeasible = (case1.replace("shaft_angle_deg = 13.0", "shaft_angle_deg = 0.5", 1)
                  .replace("cone_angle_deg = 2.0", "cone_angle_deg = 8.0", 1)
                  .replace("cone_angle_deg = 0.8", "cone_angle_deg = 8.0", 1))
    assert infeasible.count("cone_angle_deg = 8.0") == 2 and "shaft_angle_deg = 0.5" in infeasible
    files["infeasible"].write_text(infeasible)
    (tmp_path / "a_file").write_text("not a folder")
    return files


# (argv with {placeholders} from bad_files, words the message must contain)
ONE_LINE_ERRORS = {
    "missing-file": (["design", "{missing}"], ["no_such_file.toml", "no such file"]),
    "missing-file-tca": (["tca", "{missing}", "--positions", "5"], ["no_such_file.toml"]),
    "bad-toml": (["design", "{badtoml}"], ["bad_syntax.toml", "TOML"]),
    "unknown-key": (["tca", "{unknown}", "--positions", "5"], ["gear.foo_mm", "unknown key"]),
    "bad-value": (["sweep", "{badvalue}", "--samples", "2", "--positions", "3"], ["pinion.teeth", "5"]),
    "file-is-dir": (["design", "{dir}"], ["cannot read"]),
    "tca-positions-0": (["tca", "{case1}", "--positions", "0"], ["--positions", "0"]),
    "tca-pairs-2": (["tca", "{case1}", "--pairs", "2"], ["--pairs", "2"]),
    "tca-pairs-11": (["tca", "{case1}", "--pairs", "11"], ["--pairs", "11"]),
    "tca-vertical-inf": (["tca", "{case1}", "--vertical", "inf"], ["--vertical", "inf"]),
    "sweep-samples-0": (["sweep", "{case1}", "--samples", "0"], ["--samples", "0"]),
    "sweep-positions-1": (["sweep", "{case1}", "--positions", "1"], ["--positions", "1"]),
    "sweep-dx-max-negative": (["sweep", "{case1}", "--dx-max", "-1"], ["--dx-max", "-1"]),
    "sweep-dx-max-nan": (["sweep", "{case1}", "--dx-max", "nan"], ["--dx-max", "nan"]),
    "sweep-horizontal-max-5": (["sweep", "{case1}", "--horizontal-max", "5"], ["--horizontal-max", "5"]),
    "paper-positions-3": (["paper", "--out", "{blocked_out}", "--positions", "3"], ["--positions", "3"]),
    "paper-out-unwritable": (["paper", "--out", "{blocked_out}", "--positions", "10"], ["--out"]),
    "design-infeasible": (["design", "{infeasible}"], ["infeasible.toml", "shaft_angle_deg"]),
    "sweep-seed-negative": (["sweep", "{case1}", "--samples", "2", "--positions", "3", "--seed", "-1"],
                            ["--seed", "-1"]),
    "tca-plot-missing-folder": (["tca", "{case1}", "--positions", "5", "--plot", "{blocked_out}/x.png"],
                                ["--plot", "does not exist"]),
    "tca-plot-unknown-format": (["tca", "{case1}", "--positions", "5", "--plot", "{dir}/plot.txt"],
                                ["--plot", ".png"]),
    "tca-dx-out-of-range": (["tca", "{case1}", "--positions", "5", "--dx", "11"], ["--dx", "11"]),
    "tca-approach-zero": (["tca", "{case1}", "--positions", "5", "--approach-um", "0"], ["--approach-um", "0"]),
    "tca-approach-nan": (["tca", "{case1}", "--positions", "5", "--approach-um", "nan"], ["--approach-um", "nan"]),
    "tca-approach-huge": (["tca", "{case1}", "--positions", "5", "--approach-um", "5000"], ["--approach-um", "5000"]),
}

# argparse's usage errors: one line "beveloid <command>: error: argument ... (see ... --help)"
ARGPARSE_ERRORS = {
    "tca-flank-up": (["tca", "{case1}", "--flank", "up"], "tca", ["--flank", "up"]),
    "tca-positions-not-int": (["tca", "{case1}", "--positions", "abc"], "tca", ["--positions", "abc"]),
    "sweep-flank-both": (["sweep", "{case1}", "--flank", "both"], "sweep", ["--flank", "both"]),
    "sweep-backend-unknown": (["sweep", "{case1}", "--backend", "gpu"], "sweep", ["--backend", "gpu"]),
}


def _fill(argv, files):
    return [a.format(**files) for a in argv]


@pytest.mark.parametrize("argv, words", ONE_LINE_ERRORS.values(), ids=ONE_LINE_ERRORS.keys())
def test_bad_input_one_line_exit_2(capsys, bad_files, argv, words):
    rc, out, err = run_cli(capsys, _fill(argv, bad_files))
    assert rc == 2
    assert out == ""
    assert "Traceback" not in err
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("beveloid: error: ")
    for w in words:
        assert w in lines[0], (w, lines[0])
    assert not (bad_files["blocked_out"]).exists()  # `paper` never wrote anything


@pytest.mark.parametrize("argv, command, words", ARGPARSE_ERRORS.values(), ids=ARGPARSE_ERRORS.keys())
def test_bad_option_argparse_exit_2(capsys, bad_files, argv, command, words):
    rc, out, err = run_cli(capsys, _fill(argv, bad_files))
    assert rc == 2
    assert out == ""
    assert "Traceback" not in err
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith(f"beveloid {command}: error: argument ")
    for w in words:
        assert w in lines[0]


# ------------------------------------------------------------------------------------------
# 4. --plot
# ------------------------------------------------------------------------------------------
def test_tca_plot_writes_png(capsys, tmp_path):
    out_png = tmp_path / "tca.png"
    data = run_json(capsys, ["tca", CASE2, "--positions", 7, "--dx", "0.2", "--plot", out_png, "--json"])
    assert set(data["flanks"]) == {"left", "right"}  # --plot leaves stdout pure JSON
    blob = out_png.read_bytes()
    assert len(blob) > 1000 and blob.startswith(PNG_MAGIC)

    one = tmp_path / "right.png"
    rc, out, _ = run_cli(capsys, ["tca", CASE1, "--positions", 7, "--flank", "right", "--plot", one])
    assert rc == 0 and "right" in out
    assert one.read_bytes().startswith(PNG_MAGIC)


# ------------------------------------------------------------------------------------------
# 5. sweep --json contract and seeds
# ------------------------------------------------------------------------------------------
STAT_KEYS = ("mean", "std", "min", "p05", "p50", "p95", "max")


def check_stats(s, max_count):
    assert isinstance(s["count"], int) and 0 <= s["count"] <= max_count
    if s["count"] == 0:
        return
    for k in STAT_KEYS:
        assert _is_finite_number(s[k]), k
    assert s["min"] <= s["p05"] <= s["p50"] <= s["p95"] <= s["max"]
    assert s["min"] - 1e-12 <= s["mean"] <= s["max"] + 1e-12
    assert s["std"] >= 0


def _sweep_json(capsys, seed, samples=16, positions=7, extra=()):
    return run_json(capsys, ["sweep", CASE1, "--samples", samples, "--positions", positions, "--seed", seed,
                             "--json", *extra])


def test_sweep_json_contract(capsys):
    samples, positions = 16, 7
    o = _sweep_json(capsys, 1, samples, positions, extra=["--dx-max", "0.1", "--flank", "left"])
    assert o["samples"] == samples and o["positions"] == positions and o["flank"] == "left"
    assert isinstance(o["contact_points_solved"], int) and o["contact_points_solved"] == samples * positions
    assert set(o["status_counts"]) == STATUSES
    assert all(isinstance(v, int) and v >= 0 for v in o["status_counts"].values())
    assert sum(o["status_counts"].values()) == o["contact_points_solved"]
    assert o["ranges"]["dx_mm"] == 0.1
    assert o["ranges"]["dy_mm"] == sweep.DEFAULT_RANGES["dy_mm"]
    assert o["backend"] in ("compiled", "numpy")
    fr = {k: o[k] for k in ("fraction_sets_with_edge_contact", "fraction_sets_with_contact_off_flank",
                            "fraction_sets_entirely_off_flank")}
    for k, v in fr.items():
        assert 0.0 <= v <= 1.0, k
        assert (v * samples) == pytest.approx(round(v * samples)), k  # a fraction of the sets
    assert fr["fraction_sets_entirely_off_flank"] <= fr["fraction_sets_with_contact_off_flank"]
    counts = o["status_counts"]
    assert (counts["edge"] > 0) == (fr["fraction_sets_with_edge_contact"] > 0)
    assert (counts["outside"] + counts["failed"] > 0) == (fr["fraction_sets_with_contact_off_flank"] > 0)
    n_with_contact = round(samples * (1 - fr["fraction_sets_entirely_off_flank"]))
    for key in ("pinion_path_shift_mm", "gear_path_shift_mm", "te_peak_to_peak_urad"):
        check_stats(o[key], samples)
        assert o[key]["count"] == n_with_contact, key
    lo, hi = o["pinion_angle_window_rad"]
    assert lo < hi
    for t in TIMING_KEYS:
        assert _is_finite_number(o[t]) and o[t] >= 0
    assert o["seconds_total"] >= o["seconds"]
    sens = o["sensitivity"]
    for key in ("pinion_axial_shift_mm_per_unit", "gear_axial_shift_mm_per_unit", "gear_angle_urad_per_unit"):
        assert set(sens[key]) == set(sweep.DEFAULT_RANGES)
        assert all(_is_finite_number(v) for v in sens[key].values())


def test_sweep_seed_reproducible(capsys):
    a = _sweep_json(capsys, 7)
    b = _sweep_json(capsys, 7)
    c = _sweep_json(capsys, 8)
    strip = lambda o: {k: v for k, v in o.items() if k not in TIMING_KEYS}  # noqa: E731
    assert TIMING_KEYS <= set(a)
    assert strip(a) == strip(b)
    assert a["pinion_path_shift_mm"] != c["pinion_path_shift_mm"]
    assert a["gear_path_shift_mm"] != c["gear_path_shift_mm"]
    assert a["pinion_angle_window_rad"] == c["pinion_angle_window_rad"]  # the window is the aligned one


# ------------------------------------------------------------------------------------------
# 6. backends agree; backend resolution
# ------------------------------------------------------------------------------------------
def test_sweep_backends_agree(geom1):
    pytest.importorskip("numba")
    options = sweep.Options(flank="right", samples=50, positions=20, seed=3)
    rn = sweep.analyze(geom1, options, solver=Solver("numpy"))
    rc = sweep.analyze(geom1, options, solver=Solver("compiled"))
    assert rn.backend == "numpy" and rc.backend == "compiled"
    np.testing.assert_array_equal(rn.errors, rc.errors)
    np.testing.assert_array_equal(rn.status_codes, rc.status_codes)
    assert len(set(rn.status_codes.ravel().tolist())) > 1  # not a trivial comparison
    for a, b in ((rn.pinion_shift_mm, rc.pinion_shift_mm), (rn.gear_shift_mm, rc.gear_shift_mm)):
        np.testing.assert_array_equal(np.isnan(a), np.isnan(b))
        assert np.isfinite(a).any()
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-9, equal_nan=True)


def test_solved_contact_points_compiled_pass_is_the_surface(geom1):
    """The sweep's compiled contact-point pass gives the whole-array surface points where the
    status carries numbers (ok and edge) and nan elsewhere."""
    pytest.importorskip("numba")
    ref = tca.reference_contact(geom1, "right")
    p1 = geom1.pitch_angles[0]
    grid = ref.pinion_angle + np.linspace(-2.5 * p1, 2.5 * p1, 40)  # into and out of mesh
    errors = sweep.draw_errors(6, None, 5, None)
    sol = tca.solve_grid(geom1, "right", errors, grid, solver=Solver("compiled"))
    codes = set(sol.status.ravel().tolist())
    assert {0, 1} <= codes and len(codes) > 2  # ok, edge and some without numbers
    P1c, P2c = tca.solved_contact_points(geom1, "right", sol.x, sol.status, solver=Solver("compiled"))
    P1n, P2n = tca.solved_contact_points(geom1, "right", sol.x, sol.status, solver=Solver("numpy"))
    Q1, Q2 = tca.contact_points(geom1, "right", sol.x)
    has = np.isin(sol.status, (0, 1))
    for Pc, Pn, Q in ((P1c, P1n, Q1), (P2c, P2n, Q2)):
        np.testing.assert_array_equal(np.isnan(Pc).any(axis=-1), ~has)
        np.testing.assert_array_equal(np.isnan(Pn).any(axis=-1), ~has)
        np.testing.assert_allclose(Pc[has], Q[has], rtol=0, atol=1e-9)
        np.testing.assert_allclose(Pn[has], Q[has], rtol=0, atol=0)


@pytest.mark.parametrize("errors", [
    (0.3, -0.2, 0.4, math.radians(0.1), math.radians(-0.02)),
    (0.5, 0.5, 0.5, 0.0, math.radians(0.03)),
])
def test_analyze_backends_agree(geom1, errors):
    pytest.importorskip("numba")
    rn = tca.analyze(geom1, tca.Options(positions=25, approach_mm=None, errors=errors), solver=Solver("numpy"))
    rc = tca.analyze(geom1, tca.Options(positions=25, approach_mm=None, errors=errors), solver=Solver("compiled"))
    assert set(rn.flanks) == set(rc.flanks) == {"left", "right"}
    for fl in rn.flanks:
        a, b = rn.flanks[fl], rc.flanks[fl]
        assert a.status == b.status
        assert "ok" in a.status and ("outside" in a.status or "edge" in a.status)
        np.testing.assert_array_equal(np.isnan(a.gear_angle), np.isnan(b.gear_angle))
        np.testing.assert_allclose(a.gear_angle, b.gear_angle, rtol=0, atol=1e-10, equal_nan=True)
    assert rn.backlash_um == pytest.approx(rc.backlash_um, abs=1e-6)


def test_compiled_backend_drops_reference_counting_where_nothing_is_allocated():
    """The installed numba takes _nrt (else the compiled solver silently keeps its ~28 % slower
    reference counting), and the solver's hot functions are compiled without it, the allocating
    ones with it."""
    pytest.importorskip("numba")
    from beveloid.solver import core

    assert backends._nrt_option()
    allocating = set(core.ALLOCATING)
    for name in ("scratch", "edge_scratch", "solve_paths", "contact_points"):
        assert name in allocating
    ns = backends.namespace("compiled")
    hot = ("evaluate_unchecked", "newton", "first_touch", "follow_edge", "patches_apart")
    for name in hot:
        assert name not in allocating and callable(getattr(ns, name))
    import numba

    if numba.config.DISABLE_JIT:  # NUMBA_DISABLE_JIT=1: numba hands back the Python functions, nothing is compiled
        assert all(isinstance(getattr(ns, name), types.FunctionType) for name in hot + ("solve_paths_serial",))
        return
    for name in hot:
        assert getattr(ns, name).targetoptions.get("_nrt") is False, name
    assert ns.solve_paths_serial.targetoptions.get("_nrt") is True


def test_resolve_backend(monkeypatch):
    assert Solver("numpy").backend == "numpy"
    with pytest.raises(ValueError):
        Solver("gpu")
    monkeypatch.setattr(backends, "AVAILABLE", False)
    with pytest.raises(backends.BackendError, match="numba is not installed"):
        Solver("compiled")
    assert Solver("auto").backend == "numpy"


def test_cli_without_numba(monkeypatch, capsys):
    monkeypatch.setattr(backends, "AVAILABLE", False)
    rc, out, err = run_cli(capsys, ["sweep", CASE1, "--samples", 2, "--positions", 3, "--backend", "compiled"])
    assert rc == 2 and out == ""
    assert len(err.splitlines()) == 1 and err.startswith("beveloid: error: ") and "numba" in err
    o = run_json(capsys, ["sweep", CASE1, "--samples", 3, "--positions", 4, "--json"])
    assert o["backend"] == "numpy"  # auto falls back


# ------------------------------------------------------------------------------------------
# 7. physics of the sweep
# ------------------------------------------------------------------------------------------
ZERO_RANGES = {k: 0.0 for k in sweep.DEFAULT_RANGES}


@pytest.mark.parametrize("flank", ["left", "right"])
def test_sweep_without_errors_is_the_aligned_path(geom1, flank):
    res = sweep.analyze(geom1, sweep.Options(flank=flank, samples=4, positions=15, seed=0, ranges=ZERO_RANGES))
    assert not res.errors.any()
    assert np.isin(res.status_codes, (0, 1)).all()
    for shift in (res.pinion_shift_mm, res.gear_shift_mm):
        assert np.isfinite(shift).all()
        assert np.abs(shift).max() <= 1e-9
    o = res.to_json()
    assert o["fraction_sets_with_contact_off_flank"] == 0.0
    assert o["fraction_sets_entirely_off_flank"] == 0.0
    assert o["status_counts"]["outside"] == o["status_counts"]["failed"] == 0


@pytest.mark.parametrize("case", ["case1", "case2"])
def test_axial_gear_shift_is_a_screw_motion(case, geom1, geom2):
    """dz moves the gear along its own axis: the involute helicoid slides into itself after a turn,
    so the contact stays put in space -- the pinion path does not move and the gear path moves by -dz
    in the gear's frame."""
    geom = geom1 if case == "case1" else geom2
    res = sweep.analyze(geom, sweep.Options(flank="right", samples=12, positions=15, seed=11, ranges=dict(ZERO_RANGES, dz_mm=0.5)))
    dz = res.errors[:, 2]
    assert np.all(res.errors[:, [0, 1, 3, 4]] == 0) and np.abs(dz).max() > 0.1
    has = np.isfinite(res.pinion_shift_mm)
    assert has.all()
    assert np.abs(res.pinion_shift_mm).max() < 1e-6
    assert np.abs(res.gear_shift_mm).max() > 0.1  # the gear shift is real ...
    np.testing.assert_allclose(res.gear_shift_mm, -dz, rtol=0, atol=1e-6)  # ... and exactly -dz
    sens = res.sensitivity
    assert abs(sens["pinion_axial_shift_mm_per_unit"]["dz_mm"]) < 1e-9
    assert sens["gear_axial_shift_mm_per_unit"]["dz_mm"] == pytest.approx(-1.0, abs=1e-9)


# ------------------------------------------------------------------------------------------
# 8. paper
# ------------------------------------------------------------------------------------------
UNIT_SUFFIXES = ("_mm", "_rad", "_deg", "_urad")


def _float(s):
    try:
        return float(s)
    except ValueError:
        return None


def _is_int_literal(s):
    return re.fullmatch(r"[+-]?\d+", s) is not None


@pytest.mark.slow
@pytest.mark.long_running
def test_paper(capsys, tmp_path):
    out_dir = tmp_path / "paper"
    # the smallest --positions (the studies of fixed size cost the rest), the plate tooth (the FE tooth: tests/fe)
    rc, out, err = run_cli(capsys, ["paper", "--out", out_dir, "--positions", 10, "--tooth-model", "plate"])
    assert rc == 0, err
    assert "Traceback" not in err
    report = (out_dir / "report.md").read_text()

    pngs = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", report)
    assert pngs and all(p.endswith(".png") for p in pngs)
    for p in pngs:
        blob = (out_dir / p).read_bytes()
        assert blob.startswith(PNG_MAGIC), p
    assert {p.name for p in out_dir.glob("*.png")} == set(pngs)  # nothing written but not shown
    assert sum("bearing_pattern" in p for p in pngs) >= 2  # aligned and under errors (issue 11)
    data_csvs = re.findall(r"Data: (\S+\.csv)", report)
    assert data_csvs
    for c in data_csvs:
        assert (out_dir / c).is_file(), c
    assert "table1.csv" in report
    _check_report_says_what_it_holds(report)

    # Table 1: 28 printed values, each within one unit of its last printed digit -- rechecked here,
    # with the sign (the printed values are signed)
    with open(out_dir / "table1.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 28
    for r in rows:
        assert r["within_last_printed_digit"] == "True", r
        printed, computed = r["printed"], float(r["computed"])
        dec = len(printed.split(".")[1]) if "." in printed else 0
        assert abs(computed - float(printed)) <= 10.0 ** -dec * (1 + 1e-9), r
        q = r["quantity"]
        assert q in ("x_t", "xi_t") or q.endswith("(deg)") or q.endswith("(mm)"), q

    # figure data: a unit on every real-valued column; empty cells exactly where off the flanks
    for c in data_csvs:
        with open(out_dir / c, newline="") as f:
            reader = csv.reader(f)
            header = next(reader)
            body = list(reader)
        assert body, c
        cols = {h: [row[i] for row in body] for i, h in enumerate(header)}
        for h, vals in cols.items():
            present = [v for v in vals if v != ""]
            if present and all(_float(v) is not None for v in present) \
                    and not all(_is_int_literal(v) for v in present):
                assert h.endswith(UNIT_SUFFIXES), (c, h)
        for h in ("pinion_angle_rad", "gear_angle_rad", "transmission_error_urad", "pinion_z_mm", "gear_z_mm"):
            assert h in cols, (c, h)
        for i, st in enumerate(cols["status"]):
            assert st in STATUSES
            contact = [cols[h][i] for h in ("gear_angle_rad", "pinion_x_mm", "gear_z_mm")]
            if st in ("ok", "edge"):
                assert all(math.isfinite(float(v)) for v in contact), (c, i)
            else:
                assert all(v == "" for v in contact), (c, i)


def _check_report_says_what_it_holds(report):
    """Each case's line cites that case's paper value; the summary's counts are named for what they
    count; the whole run's time closes the report; the title (and --help) name every part."""
    from beveloid.studies import PAPER_CONTENTS
    from beveloid.studies.crowning import PAPER_ALIGNED_TE_URAD
    from beveloid.studies.paper import PAPER_EDGE_ONSET_MM

    lines = report.splitlines()
    assert lines[0].endswith(PAPER_CONTENTS) and "Figs 24-25" in PAPER_CONTENTS and "micro-geometry" in PAPER_CONTENTS
    assert report.count("\n## ") >= 5 and [x for x in lines if x.startswith("## ")][-1] == "## This run"
    assert "computed in" in report.split("## This run")[1] and "Computed with" not in report
    for case in ("case1", "case2"):
        onset = [x for x in lines if x.startswith(f"- {case}: the path reaches")]
        assert len(onset) == 1
        other = "case2" if case == "case1" else "case1"
        assert f"paper, {other}" not in onset[0], onset[0]
        if case in PAPER_EDGE_ONSET_MM:
            assert f"paper, {case}: edge contact begins at dq = {PAPER_EDGE_ONSET_MM[case]:g} mm" in onset[0]
        aligned = [x for x in lines if x.startswith(f"- {case}: TE peak-to-peak")]
        assert len(aligned) == 1 and aligned[0].endswith(f"(paper, {case}: {PAPER_ALIGNED_TE_URAD[case]:g} urad)")
    head = next(x for x in lines if x.startswith("| figure | case | errors"))
    assert "| surface contacts | edge contacts |" in head and "points on the flank" not in report
    assert "status `edge`" in report and "status `ok`" in report
    for row in (x for x in lines if re.match(r"\| 1\d \| case", x)):
        surface, edge = (re.findall(r"(\d+)/(\d+)", c) for c in row.split("|")[6:8])
        assert int(surface[0][0]) + int(edge[0][0]) <= int(surface[0][1]) == int(edge[0][1]), row


def test_paper_help_names_every_part(capsys):
    from beveloid.studies import PAPER_CONTENTS

    assert cli.main(["--help"]) == 0
    text = " ".join(capsys.readouterr().out.split())
    assert f"paper Reproduce {' '.join(PAPER_CONTENTS.split())}" in text


# ------------------------------------------------------------------------------------------
# 9. design --json
# ------------------------------------------------------------------------------------------
DESIGN_TOP = ("working_normal_pressure_angle_deg", "fpd_angle_left_deg", "fpd_angle_right_deg")
DESIGN_MEMBER = ("helix_angle_deg", "profile_shift", "transverse_angular_factor", "mounting_distance_mm",
                 "working_cone_angle_deg", "working_helix_angle_deg", "working_pitch_radius_mm",
                 "reference_pitch_radius_mm")


def test_design_json_contract(capsys):
    o = run_json(capsys, ["design", CASE2, "--json"])
    for k in DESIGN_TOP:
        assert _is_finite_number(o[k]), k
    d = design(load_spec(CASE2))
    assert o["working_normal_pressure_angle_deg"] == pytest.approx(math.degrees(d.working_normal_pressure_angle))
    spec = load_spec(CASE2)
    for member in ("pinion", "gear"):
        m = o[member]
        for k in DESIGN_MEMBER:
            assert _is_finite_number(m[k]), (member, k)
        assert m["working_pitch_radius_mm"] > 0 and m["reference_pitch_radius_mm"] > 0
        assert m["helix_angle_deg"] == pytest.approx(math.degrees(d.member(member).helix_angle))
    # the pinion's helix angle and profile shift are inputs: echoed unchanged
    assert o["pinion"]["helix_angle_deg"] == pytest.approx(spec.pinion.helix_angle_deg, abs=1e-12)
    assert o["pinion"]["profile_shift"] == pytest.approx(spec.pinion.profile_shift, abs=1e-12)

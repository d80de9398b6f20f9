"""``beveloid export``: files named as documented, one line per file, one-line refusals (exit 2)."""
from __future__ import annotations

import sys
from pathlib import Path

import pytest
import trimesh

from beveloid.cli import main
from beveloid.export import formats

SMALL = """
[pair]
normal_module_mm = 2.0
normal_pressure_angle_deg = 20.0
shaft_angle_deg = 13.0
offset_mm = 36.0

[pinion]
teeth = 15
cone_angle_deg = 2.0
helix_angle_deg = 23.0
profile_shift = 0.3
face_width_mm = 8.0
bore_diameter_mm = {bore}

[gear]
teeth = 19
cone_angle_deg = 0.8
face_width_mm = 10.0
"""


def _spec(tmp_path, bore=12.0):
    path = tmp_path / "small.toml"
    path.write_text(SMALL.format(bore=bore), encoding="utf-8")
    return path


def test_export_writes_one_file_per_member_and_reports_it(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["export", str(_spec(tmp_path)), "--format", "stl", "--member", "gear", "--out", str(out)]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert [p.name for p in out.iterdir()] == ["small_gear.stl"]
    assert len(lines) == 1 and lines[0].startswith(f"{out / 'small_gear.stl'}: gear (19 teeth), volume ")
    assert trimesh.load(out / "small_gear.stl", file_type="stl").is_watertight


def test_a_bore_through_the_root_exits_2_with_one_line(tmp_path, capsys):
    assert main(["export", str(_spec(tmp_path, bore=40.0)), "--member", "pinion", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert err.startswith("beveloid: error: pinion.bore_diameter_mm = 40: must be below the smallest root diameter")


def test_without_the_cad_extra_it_says_what_to_install(tmp_path, capsys, monkeypatch):
    """Run from a checkout, the hint is the checkout's own install command (the package is on no index)."""
    root = Path(__file__).resolve().parents[2]
    # the package as it runs from its checkout (under `pytest` after `pip install .` it runs installed)
    monkeypatch.setattr(formats, "source_checkout", lambda: root)
    monkeypatch.setitem(sys.modules, "OCP", None)  # `import OCP...` now raises ImportError
    monkeypatch.setitem(sys.modules, "OCP.BRepBuilderAPI", None)
    assert main(["export", str(_spec(tmp_path)), "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err == (f'beveloid: error: beveloid export --format step needs OCP: pip install ".[cad]" in the source'
                   f" checkout {root}\n")
    assert not list(tmp_path.glob("*.st*"))


def test_an_installed_copy_is_told_the_extras_requirements(monkeypatch):
    """Not in a checkout: the installed metadata's requirements of the extra, which need no index for beveloid."""
    monkeypatch.setattr(formats, "source_checkout", lambda: None)
    monkeypatch.setattr(formats.importlib.metadata, "requires",
                        lambda name: ["numpy>=1.26", 'cadquery-ocp>=8.0; extra == "cad"', "trimesh>=4.0; extra == 'cad'",
                                      'pytest; extra == "test"'])
    hint = formats.install_hint(formats.WRITERS["stl"])
    assert hint == "beveloid export --format stl needs trimesh: pip install 'cadquery-ocp>=8.0' 'trimesh>=4.0' (the 'cad' extra)"


def test_the_writer_registry_drives_the_formats_and_the_hint(tmp_path, capsys, monkeypatch):
    """A new writer is one entry: --format offers it, --help describes it, and its missing extra is named."""
    vtu = formats.Writer("vtu", "vtu", "fe", ("a_module_that_is_not_installed",), "VTU of the tooth (test)",
                         "chord", None, None, None)
    monkeypatch.setitem(formats.WRITERS, "vtu", vtu)
    monkeypatch.setattr(formats, "source_checkout", lambda: Path(__file__).resolve().parents[2])
    assert main(["export", "--help"]) == 0
    help_text = " ".join(capsys.readouterr().out.split())
    assert "{step,stl,vtu}" in help_text and "vtu: VTU of the tooth (test)" in help_text
    assert main(["export", str(_spec(tmp_path)), "--format", "vtu", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("beveloid: error: beveloid export --format vtu needs a_module_that_is_not_installed: ")
    assert '".[fe]"' in err and err.count("\n") == 1
    monkeypatch.delitem(formats.WRITERS, "vtu")
    assert main(["export", str(_spec(tmp_path)), "--format", "vtu"]) == 2  # gone from the choices again
    assert "invalid choice: 'vtu'" in capsys.readouterr().err


@pytest.mark.parametrize("args", [["--format", "iges"], ["--member", "rack"]])
def test_bad_flags_are_usage_errors(tmp_path, capsys, args):
    assert main(["export", str(_spec(tmp_path)), *args]) == 2
    assert capsys.readouterr().err.count("\n") == 1


def test_out_targets_are_refused_before_exporting(tmp_path, capsys, monkeypatch):
    """--out is checked like every output target (beveloid.cli.paths) before anything is built."""
    def boom(*_args, **_kwargs):
        raise AssertionError("exported despite a bad --out")

    monkeypatch.setattr("beveloid.export.export", boom)
    a_file = tmp_path / "a_file"
    a_file.write_text("x", encoding="utf-8")
    for target, words in (("", "an empty name"), (str(a_file), "exists and is not a folder"),
                          (str(tmp_path / ("d" * 256)), "more than the 255")):
        assert main(["export", str(_spec(tmp_path)), "--out", target]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and err.startswith("beveloid: error: --out = ") and words in err, err


def test_a_full_disk_leaves_no_file_and_no_folder(tmp_path, capsys, monkeypatch):
    """issue 60: a full disk during export left a partial file and the folder the run made: now one line
    naming --out and the reason, the files of the run removed, the folder it made gone; a folder that was
    there keeps what it held."""
    import dataclasses
    import errno

    stl = formats.WRITERS["stl"]
    calls = []

    def fills_the_disk(shapes, path):
        calls.append(path)
        if len(calls) == 2:  # the gear: the disk is full half-way through
            Path(path).write_bytes(b"solid partial\n")
            raise OSError(errno.ENOSPC, "No space left on device")
        return stl.write(shapes, path)

    monkeypatch.setitem(formats.WRITERS, "stl", dataclasses.replace(stl, write=fills_the_disk))
    out = tmp_path / "new"
    assert main(["export", str(_spec(tmp_path)), "--format", "stl", "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err == f"beveloid: error: --out = {out}: cannot write there (No space left on device)\n"
    assert not out.exists()
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "notes.txt").write_text("mine")
    calls.clear()
    assert main(["export", str(_spec(tmp_path)), "--format", "stl", "--out", str(mine)]) == 2
    assert [p.name for p in mine.iterdir()] == ["notes.txt"]


@pytest.mark.solver  # `design` runs the solver
def test_a_flank_the_step_faces_cannot_follow_is_said_by_design_and_refused_in_one_line(tmp_path, capsys):
    """issue 60: 6 um of pinion profile crowning folds the right flank by 0.87 um next to its form limit:
    STEP export printed a traceback (BRepCheck_Analyzer, exit 1) after fitting; 10 um could not be exported
    in either format while `design` said nothing.  Now `design` says it first, STEP export refuses it in
    one line (exit 2) before any fitting, and STL builds it; 5 um (a 0.36 um fold) stays exportable."""
    import json

    text = (Path(__file__).resolve().parents[1] / "data" / "issue60_pair.toml").read_text()
    specs = {}
    for um in (5, 6, 10):
        specs[um] = tmp_path / f"pc{um}.toml"
        specs[um].write_text(text.replace("profile_crowning_um = 6.0", f"profile_crowning_um = {um:g}.0"))

    def design_says(um):
        assert main(["design", str(specs[um]), "--json"]) == 0
        return [s["message"] for s in json.loads(capsys.readouterr().out)["tooth_status"]
                if s["status"] == "not exportable"]

    assert design_says(5) == []
    six = design_says(6)
    assert len(six) == 1 and six[0].startswith("export as STEP: pinion: the right flank turns back toward the axis")
    ten = design_says(10)
    assert len(ten) == 1 and ten[0].startswith("export (STEP and STL): pinion: the right flank turns back")
    assert main(["export", str(specs[6]), "--format", "step", "--member", "pinion", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err and six[0].split(": ", 1)[1] in err
    assert not list(tmp_path.glob("*.step"))

"""export()'s out_dir keeps the one output rule of the CLI (beveloid.outputs, issue 29 item 5): it
creates the named folder only, and a missing parent is refused in one line before anything is built."""
from __future__ import annotations

import dataclasses

import pytest

from beveloid import export as export_module
from beveloid.errors import ErrorCode
from beveloid.export import ExportOptions, export
from beveloid.outputs import OutputError


class _Built:
    teeth = 3
    max_error_um = 0.0


@pytest.fixture
def recording_writer(monkeypatch):
    """The STL writer with its build and write replaced by recorders (the test is about folders only)."""
    calls = []

    def build(*_args):
        calls.append("build")
        return _Built()

    def write(_shapes, path):
        calls.append(path)
        path.write_bytes(b"solid")
        return 1.0, 1

    writer = dataclasses.replace(export_module.WRITERS["stl"], build=build, place=lambda built, _place: built,
                                 write=write)
    monkeypatch.setitem(export_module.WRITERS, "stl", writer)
    return calls


def test_a_missing_parent_is_refused_before_building(small_pair, tmp_path, recording_writer, monkeypatch):
    monkeypatch.chdir(tmp_path)  # a short relative path: the message shows it whole
    with pytest.raises(OutputError) as err:
        export(small_pair, ExportOptions(format="stl", members=("pinion",), out_dir="missing/deeper/out"))
    text = str(err.value)
    assert err.value.code == ErrorCode.OUTPUT and "\n" not in text
    assert text.startswith("out_dir = missing/deeper/out: the folder missing/deeper does not exist"), text
    assert recording_writer == [] and not (tmp_path / "missing").exists()  # nothing built, no tree made


def test_the_named_folder_is_created_in_an_existing_parent(small_pair, tmp_path, recording_writer):
    target = tmp_path / "new"
    result = export(small_pair, ExportOptions(format="stl", members=("pinion",), out_dir=target, stem="s"))
    assert target.is_dir() and [f.path for f in result.files] == [target / "s_pinion.stl"]
    assert recording_writer == ["build", target / ".s_pinion.partial.stl"]  # renamed when whole
    assert sorted(p.name for p in target.iterdir()) == ["s_pinion.stl"]


def test_a_file_in_the_way_is_refused(small_pair, tmp_path, recording_writer):
    (tmp_path / "f").write_text("x", encoding="utf-8")
    with pytest.raises(OutputError, match="exists and is not a folder"):
        export(small_pair, ExportOptions(format="stl", members=("pinion",), out_dir=tmp_path / "f"))
    assert recording_writer == []

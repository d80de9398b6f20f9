"""`beveloid paper --out`: a run writes beside the target and moves its files in when done."""
from __future__ import annotations

import threading

import pytest

from beveloid.studies import output, paper


def _write(folder, tag, names=("report.md", "fig10.png", "fig10.csv")):
    for name in names:
        (folder / name).write_text(f"{tag}\n")


def _files(folder):
    """(name, text) of the files in folder, without the staging folders of runs still writing."""
    return {(p.name, p.read_text()) for p in folder.iterdir() if not p.name.startswith(output.STAGE_PREFIX)}


def test_two_interleaved_runs_leave_one_runs_files(tmp_path):
    target = tmp_path / "same"
    first_staged, second_done = threading.Event(), threading.Event()

    def slow_run():
        with output.staged_folder(target) as stage:
            first_staged.set()
            second_done.wait(30)
            _write(stage, "slow")

    t = threading.Thread(target=slow_run)
    t.start()
    first_staged.wait(30)
    with output.staged_folder(target) as stage:
        _write(stage, "fast")
        assert not (target / "report.md").exists()  # nothing is in place while a run writes
    assert _files(target) == {
        ("report.md", "fast\n"), ("fig10.png", "fast\n"), ("fig10.csv", "fast\n")}
    second_done.set()
    t.join(30)
    # the run that finished last replaced every file: no mix, no partial folder left
    assert {p.name for p in target.iterdir()} == {"report.md", "fig10.png", "fig10.csv"}
    assert _files(target) == {
        ("report.md", "slow\n"), ("fig10.png", "slow\n"), ("fig10.csv", "slow\n")}


def test_a_failed_run_leaves_the_folder_as_it_was(tmp_path):
    target = tmp_path / "out"
    target.mkdir()
    (target / "report.md").write_text("before\n")
    (target / "notes.txt").write_text("mine\n")
    with pytest.raises(ZeroDivisionError):
        with output.staged_folder(target) as stage:
            _write(stage, "half")
            1 / 0
    assert {(p.name, p.read_text()) for p in target.iterdir()} == {("report.md", "before\n"), ("notes.txt", "mine\n")}


def test_paper_run_writes_through_the_staged_folder(tmp_path, monkeypatch):
    target = tmp_path / "b"  # created: its parent exists (a missing tree is refused: below)
    seen = {}

    def fake_study(out, positions, progress, tooth_model=None, workers=None):
        seen["folder"] = out
        seen["in place while writing"] = (target / "report.md").exists()
        _write(out, "run")

    monkeypatch.setattr(paper, "write_study", fake_study)
    messages = []
    assert paper.run(target, positions=10, progress=messages.append) == target / "report.md"
    assert seen["folder"].parent == target and seen["folder"].name.startswith(output.STAGE_PREFIX)
    assert seen["in place while writing"] is False
    assert (target / "report.md").read_text() == "run\n" and not seen["folder"].exists()
    assert messages[-1].endswith(f": {target / 'report.md'}")


def test_a_missing_parent_is_refused_and_nothing_is_created(tmp_path):
    """The one output rule (beveloid/outputs.py) on the API's folder too: the named folder is
    created, a missing tree is not."""
    from beveloid.outputs import OutputError

    target = tmp_path / "missing" / "deep" / "paper"
    with pytest.raises(OutputError, match=r"^out_dir = .*: the folder .* does not exist; create it first"):
        with output.staged_folder(target):
            pass
    assert not (tmp_path / "missing").exists()
    with output.staged_folder(tmp_path / "made") as stage:
        _write(stage, "x")
    assert _files(tmp_path / "made") == {("report.md", "x\n"), ("fig10.png", "x\n"), ("fig10.csv", "x\n")}

"""beveloid optimize stopped early (issue 60): a Ctrl-C before the first candidate leaves no request.json
and no empty candidates/ behind, and says so; a run whose front is empty lists no pareto_<n>.toml and
prints no "None" picks."""
from __future__ import annotations

from pathlib import Path

import pytest

from beveloid import interrupts
from beveloid.cli import main
from beveloid.cli import optimize as cli
from beveloid.optimize import search

CASE1 = Path(__file__).resolve().parents[2] / "beveloid" / "data" / "case1.toml"
QUICK = ["--tooth-model", "plate", "--grid", "5x5", "--positions", "3", "--workers", "1"]


@pytest.fixture
def fresh_interrupts(monkeypatch):
    monkeypatch.setitem(interrupts._state, "seen", False)
    monkeypatch.setitem(interrupts._state, "reported", False)


def _args(out):
    return ["optimize", str(CASE1), "--vary", "pinion.lead_crowning_um=5:40", "--torque-nm", "200", "--objectives",
            "pressure", "--budget", "4", "--population", "4", "--constraints", "none", "--out", str(out), *QUICK]


def test_ctrl_c_during_the_unmodified_design_leaves_nothing(tmp_path, capsys, monkeypatch, fresh_interrupts):
    def ctrl_c(*a, **k):
        raise KeyboardInterrupt

    monkeypatch.setattr(search, "evaluate", ctrl_c)  # the baseline's evaluation
    out = tmp_path / "opt"
    assert main(_args(out)) == 130
    err = capsys.readouterr().err
    assert "nothing written (the folder, made by this run, is removed)" in err
    assert not out.exists()
    existing = tmp_path / "mine"
    existing.mkdir()
    (existing / "notes.txt").write_text("mine")
    assert main(_args(existing)) == 130
    assert sorted(p.name for p in existing.iterdir()) == ["notes.txt"]  # the folder as it was


def test_ctrl_c_before_the_first_candidate_says_what_is_kept(tmp_path, capsys, monkeypatch, fresh_interrupts):
    """The unmodified design (outside the range) finished, then Ctrl-C: no empty report, no pareto file
    listed that was never written, no "None" picks; its numbers are kept for --resume."""
    def ctrl_c(task):
        raise KeyboardInterrupt

    monkeypatch.setattr(search, "evaluate_task", ctrl_c)
    out = tmp_path / "opt"
    assert main(_args(out)) == 130
    std = capsys.readouterr()
    assert "None" not in std.out + std.err and "pareto_" not in std.out
    assert f"stopped (interrupted (Ctrl-C)) before the first candidate; the unmodified design's numbers are kept in {out}" \
        in std.err
    assert sorted(p.name for p in out.iterdir()) == ["candidates", "request.json"]
    assert [p.name for p in (out / "candidates").iterdir()] == ["baseline.json"]


def test_an_empty_front_lists_no_pareto_files_and_no_none_picks(capsys):
    summ = {"varied": [{"key": "pinion.tip_relief_um"}], "file": "my.toml", "evaluated": 8, "seconds": 1.0,
            "executor": "1 worker", "objectives": ["te_peak_to_peak_urad"], "constraints": "rating",
            "torques_nm": [50.0, 100.0], "baseline": {"objectives": {"te_peak_to_peak_urad": 10.8}, "dominated_by": []},
            "pareto": [], "picks": {"lowest_te": None, "lowest_pressure": None, "knee": None},
            "figures": ["pareto.png", "te_vs_torque.png"]}
    cli._print(summ, "opt")
    text = capsys.readouterr().out
    assert "None" not in text and "pareto_" not in text
    assert "Pareto front: empty: no candidate is ok and passes `beveloid rating`'s verdict at 100 N m" in text
    assert "Files in opt: candidates.csv, pareto.csv, summary.json, pareto.png, te_vs_torque.png" in text

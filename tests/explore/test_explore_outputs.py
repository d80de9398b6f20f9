"""What explore writes and how it stops (issues 45 and 47): the CSV text made column by column and by
the workers is the text of a plain csv.writer over the rows; the Pareto front of three objectives; a
damaged chunk is computed again; Ctrl-C after the last chunk writes the data files and says how to
draw the rest, a second Ctrl-C stops at once; Ctrl-C at the terminal while the worker processes
start is one line (they never see it)."""
from __future__ import annotations

import csv
import io
import math
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from beveloid import interrupts
from beveloid.cli import main
from beveloid.explore import pareto, report
from beveloid.spec import example_text


@pytest.fixture(scope="module")
def case1(tmp_path_factory):
    path = tmp_path_factory.mktemp("spec") / "case1.toml"
    path.write_text(example_text("case1"))
    return str(path)


@pytest.fixture
def fresh_interrupts(monkeypatch):
    """The Ctrl-C marks of beveloid.interrupts as a fresh command has them (and back after the test)."""
    monkeypatch.setitem(interrupts._state, "seen", False)
    monkeypatch.setitem(interrupts._state, "reported", False)


def reference_csv(table: dict, rows=None) -> bytes:
    """A CSV file as a plain csv.writer writes it: one cell per value (text as is, true/false, int, float
    by repr, empty for a non-finite float), row by row."""
    def cell(v):
        if isinstance(v, (str, np.str_)):
            return str(v)
        if isinstance(v, (bool, np.bool_)):
            return "true" if v else "false"
        if isinstance(v, (int, np.integer)):
            return str(int(v))
        return repr(float(v)) if math.isfinite(v) else ""

    buf = io.StringIO(newline="")
    w = csv.writer(buf)
    w.writerow(list(table))
    for i in range(len(table["design"])) if rows is None else rows:
        w.writerow([cell(table[k][i]) for k in table])
    return buf.getvalue().encode()


def test_the_csv_text_is_a_plain_csv_writers():
    table = {
        "design": np.arange(7),
        "status": np.array(["ok", 'say "no", twice', "two\nlines", "a\rb", "", "μm, γ", "plain"]),
        "reason": np.array(["", "x,y", "", '"', "", "z", ""], dtype=object).astype(str),
        "value_mm": np.array([0.1 + 0.2, np.nan, -0.0, 1e16, np.inf, 5e-324, -1.7976931348623157e308]),
        "count": np.array([1, -2, 0, 10 ** 15, 7, 3, 4]),
        "flag": np.array([True, False, True, False, True, False, True]),
    }
    on_front = np.array([True, False, False, True, False, True, False])
    # the rows in two chunks, each made into text on its own, then joined
    parts = [report.csv_rows({k: v[s] for k, v in table.items()}) for s in (slice(0, 4), slice(4, 7))]
    keys = list(table)
    full = dict(table, pareto=on_front)
    assert report.csv_bytes(keys, parts, on_front) == reference_csv(full)
    assert report.csv_bytes(keys, parts, on_front, keep=on_front) == reference_csv(full, np.nonzero(on_front)[0])
    none = np.zeros(7, dtype=bool)
    assert report.csv_bytes(keys, parts, none, keep=none) == reference_csv(full, [])


def test_the_pareto_front_of_three_objectives_is_every_undominated_row():
    rng = np.random.default_rng(5)
    P = rng.integers(0, 9, size=(1300, 3)).astype(float)  # ties and equal rows
    P[rng.random(1300) < 0.05, 1] = np.nan
    got = pareto.front(P)
    finite = np.isfinite(P).all(axis=1)
    Q = P[finite]
    dominated = ((Q[:, None, :] <= Q[None, :, :]).all(axis=2) & (Q[:, None, :] < Q[None, :, :]).any(axis=2)).any(axis=0)
    expected = np.zeros(len(P), dtype=bool)
    expected[np.nonzero(finite)[0][~dominated]] = True
    np.testing.assert_array_equal(got, expected)
    assert 0 < expected.sum() < finite.sum()


@pytest.mark.parametrize("k", [2, 3])
def test_the_pareto_front_is_pymoos_first_front_of_the_finite_rows(k):
    """explore's and optimize's front is pymoo's non-dominated sorting (a dependency), not a filter of our own."""
    from pymoo.util.nds.non_dominated_sorting import NonDominatedSorting

    rng = np.random.default_rng(k)
    P = rng.integers(0, 6, size=(400, k)).astype(float)
    P[rng.random(400) < 0.1, 0] = np.inf
    finite = np.flatnonzero(np.isfinite(P).all(axis=1))
    first = NonDominatedSorting().do(P[finite], only_non_dominated_front=True)
    assert set(np.flatnonzero(pareto.front(P))) == set(finite[first])
    assert not pareto.front(np.full((3, k), np.nan)).any() and pareto.front(np.zeros((0, k))).shape == (0,)


def test_resume_computes_a_damaged_chunk_again(case1, tmp_path, capsys):
    out = tmp_path / "run"
    grid = ["--vary", "pinion.cone_angle_deg=1:3:3", "--chunk", "2", "--workers", "1"]
    assert main(["explore", case1, *grid, "--out", str(out)]) == 0
    whole = (out / "explore.csv").read_bytes()
    # the table the chunks hold, written by a plain csv.writer, is the file
    from beveloid.explore import run as runner
    import json

    req = runner.Request.from_json(json.loads((out / "request.json").read_text()))
    table = runner.load_table(str(out), req)
    report.mark_pareto(table, False)
    assert whole == reference_csv(table)
    (out / "chunks" / "chunk_0000001.npz").write_bytes(b"abc")  # a chunk overwritten with a few bytes
    capsys.readouterr()
    assert main(["explore", "--resume", str(out), "--workers", "1"]) == 0
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "chunk 1 (chunk_0000001.npz)" in err and "damaged" in err, err
    assert (out / "explore.csv").read_bytes() == whole
    # a chunk as an older version wrote it (one array per column, no CSV text): its text is made here
    old = out / "chunks" / "chunk_0000000.npz"
    np.savez(old, **{k: v for k, v in runner.Chunks(str(out), req).parts[0].items() if not k.startswith("_")})
    assert main(["explore", "--resume", str(out), "--workers", "1"]) == 0
    assert capsys.readouterr().err == ""
    assert (out / "explore.csv").read_bytes() == whole


def test_one_design_is_one_design(case1, tmp_path, capsys):
    assert main(["explore", case1, "--vary", "pinion.cone_angle_deg=2:2:1", "--workers", "1",
                 "--out", str(tmp_path / "one")]) == 0
    text = capsys.readouterr().out
    assert "Explored 1 of 1 design of" in text and ": 1 design\n" in text, text


def _ctrl_c_at(monkeypatch, times):
    """SIGINT ``times`` times to this process (as the terminal's Ctrl-C) as the data files are about to be
    written: after the last chunk."""
    real = report.write_data

    def ctrl_c_then_write(*a, **k):
        for _ in range(times):
            os.kill(os.getpid(), signal.SIGINT)
        return real(*a, **k)

    monkeypatch.setattr(report, "write_data", ctrl_c_then_write)


def test_ctrl_c_after_the_last_chunk_writes_the_data(case1, tmp_path, capsys, monkeypatch, fresh_interrupts):
    out = tmp_path / "run"
    _ctrl_c_at(monkeypatch, 1)
    assert main(["explore", case1, "--vary", "pinion.cone_angle_deg=1:3:2", "--workers", "1", "--out", str(out)]) == 130
    std = capsys.readouterr()
    lines = std.err.strip().splitlines()
    assert len(lines) == 2 and "Ctrl-C again to stop at once" in lines[0], lines
    assert f"`beveloid explore --resume {out}` draws them" in lines[1], lines
    assert sorted(p.name for p in out.iterdir()) == ["chunks", "explore.csv", "pareto.csv", "request.json",
                                                     "summary.json"]
    assert f"Files in {out}: explore.csv, pareto.csv, summary.json\n" in std.out
    data = (out / "explore.csv").read_bytes()
    monkeypatch.undo()
    assert main(["explore", "--resume", str(out), "--workers", "1"]) == 0
    assert all((out / name).stat().st_size > 0 for name in report.FIGURES)
    assert (out / "explore.csv").read_bytes() == data


def test_a_second_ctrl_c_stops_at_once(case1, tmp_path, capsys, monkeypatch, fresh_interrupts):
    out = tmp_path / "run"
    _ctrl_c_at(monkeypatch, 2)
    assert main(["explore", case1, "--vary", "pinion.cone_angle_deg=1:3:2", "--workers", "1", "--out", str(out)]) == 130
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 2 and f"2 of 2 designs kept in {out}" in lines[1], lines
    assert f"`beveloid explore --resume {out}` writes the outputs" in lines[1]
    assert sorted(p.name for p in out.iterdir()) == ["chunks", "request.json"]  # nothing half-written


def test_ctrl_c_while_the_workers_start_is_one_line(tmp_path, compiled_solver):
    """The terminal's Ctrl-C goes to every process of its group: the worker processes (still importing)
    must not print theirs, and are gone when the command ends."""
    out = tmp_path / "run"
    case1 = os.path.join(os.path.dirname(__file__), "..", "..", "examples", "case1.toml")
    argv = ["explore", case1, "--vary", "pinion.cone_angle_deg=1:3:400", "--mc", "20", "--chunk", "4",
            "--workers", "2", "--out", str(out)]
    proc = subprocess.Popen([sys.executable, "-m", "beveloid.cli", *argv], cwd=tmp_path, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, start_new_session=True)
    deadline = time.monotonic() + 120
    while not (out / "chunks").is_dir() and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.02)
    time.sleep(0.3)  # the worker processes are being started
    os.killpg(proc.pid, signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode in (130, -signal.SIGINT), err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err, err
    assert "interrupted" in err
    # no worker left behind (multiprocessing's resource tracker ends when it sees its parent gone)
    deadline = time.monotonic() + 10
    while _running_in_group(proc.pid) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert _running_in_group(proc.pid) == []


def _running_in_group(pgid: int) -> list[str]:
    """The command lines of the processes of a process group that have not exited (Linux's /proc; an
    exited one not yet reaped by its new parent is a zombie, state Z)."""
    running = []
    for pid in filter(str.isdigit, os.listdir("/proc")):
        try:
            with open(f"/proc/{pid}/stat") as f:
                fields = f.read().rsplit(")", 1)[1].split()  # after "pid (name)": state, ppid, pgrp, ...
            with open(f"/proc/{pid}/cmdline", "rb") as f:
                cmdline = f.read().replace(b"\0", b" ").decode(errors="replace")
        except OSError:  # gone meanwhile
            continue
        if int(fields[2]) == pgid and fields[0] != "Z":
            running.append(cmdline)
    return running


class _Recording:
    """An executor in this process that keeps its tasks (pickled and back, as to a worker process) and says
    whether its workers share this file system."""

    description = "test"

    def __init__(self, shares_files):
        self.shares_files, self.tasks = shares_files, []

    def map_unordered(self, fn, items):
        import pickle

        items = [pickle.loads(pickle.dumps(t)) for t in items]
        self.tasks += items
        return ((k, fn(t)) for k, t in enumerate(items))


@pytest.mark.parametrize("shares_files", [True, False])
def test_a_worker_on_this_file_system_writes_its_chunk_file_itself(tmp_path, monkeypatch, shares_files):
    """Issue 59: the chunk files are written where the chunks are computed (in parallel) when the workers share
    this file system (one worker, local processes), else here as they arrive (a cluster); the same files."""
    from beveloid.explore import run as runner
    from beveloid.explore.grid import Plan, parse_vary
    from beveloid.spec import load_example, spec_to_dict

    saved_by = []
    real = runner.save_chunk
    monkeypatch.setattr(runner, "save_chunk", lambda *a: saved_by.append(a[1]) or real(*a))
    plan = Plan(spec_to_dict(load_example("case1")), (parse_vary("pinion.cone_angle_deg=1:3:3"),))
    out = str(tmp_path / "run")
    req = runner.prepare(out, runner.Request(plan, {"dx_mm": 0.5}, chunk=2), resume=False)
    ex = _Recording(shares_files)
    chunks = runner.Chunks(out, req)
    saved_here = []
    real_add = chunks.add
    chunks.add = lambda i, cols, saved=False: saved_here.append(not saved) or real_add(i, cols, saved)
    assert runner.execute(out, req, ex, chunks=chunks).stop is None
    assert [t.out_dir for t in ex.tasks] == [None] + [out if shares_files else None] * 2  # (the base design: no file)
    assert saved_here == [not shares_files] * 2 and sorted(saved_by) == [0, 1]
    again = runner.Chunks(out, req)  # the files hold what this process kept
    for i in (0, 1):
        for k, v in chunks.parts[i].items():
            np.testing.assert_array_equal(again.parts[i][k], v)


def test_the_figures_drawn_as_tasks_are_the_files_drawn_here(case1, tmp_path, capsys):
    """Issue 59: each figure is a task (its PNG's bytes, drawn by a worker from the columns it shows) whose
    bytes are the file the figure's function writes itself."""
    import json

    from beveloid.explore import run as runner

    out = tmp_path / "run"
    assert main(["explore", case1, "--vary", "pinion.cone_angle_deg=1:3:3", "--vary",
                 "pinion.helix_angle_deg=18:28:2", "--workers", "1", "--out", str(out)]) == 0
    capsys.readouterr()
    req = runner.Request.from_json(json.loads((out / "request.json").read_text()))
    table = runner.load_table(str(out), req)
    report.mark_pareto(table, False)
    base = json.loads((out / "summary.json").read_text())["base_design"]
    ex = _Recording(True)
    written = report.write_figures(str(tmp_path), report.drawn_figures(req, table, base, ex))
    assert [os.path.basename(p) for p in written] == list(report.FIGURES) and len(ex.tasks) == 4
    for name in report.FIGURES:
        assert (tmp_path / name).read_bytes() == (out / name).read_bytes(), name
    here = tmp_path / "here.png"
    report.heatmap(str(here), req, table, "max_fpd_angle_deg", "largest FPD angle (deg)", base)
    assert here.read_bytes() == (out / "heatmap_fpd.png").read_bytes()
    assert not report.write_figures(str(tmp_path / "none"), report.drawn_figures(req, table, base), go_on=lambda: False)

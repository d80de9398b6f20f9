"""beveloid explore on the command line: bad input, outputs, --json, resume, an interrupted run."""
from __future__ import annotations

import csv
import dataclasses
import json
import os

import numpy as np
import pytest

import beveloid

from beveloid.cli import main
from beveloid.explore import run as runner
from beveloid.explore.grid import Plan, parse_vary
from beveloid.errors import ErrorCode, StopReason, UserError
from beveloid.spec import example_text, load_example, spec_to_dict

GRID = ["--vary", "pinion.cone_angle_deg=1:3:3", "--vary", "pinion.helix_angle_deg=18:28:3"]


@pytest.fixture(scope="module")
def case1(tmp_path_factory):
    path = tmp_path_factory.mktemp("spec") / "case1.toml"
    path.write_text(example_text("case1"))
    return str(path)


@pytest.mark.parametrize("vary, words", [
    ("pinion.cone_angel_deg=1:2:3", ["pinion.cone_angel_deg", "did you mean pinion.cone_angle_deg"]),
    ("gear.helix_angle_deg=1:2:3", ["gear.helix_angle_deg", "a design result", "pinion.helix_angle_deg and"
                                    " pair.shaft_angle_deg", "design inputs: pair.normal_module_mm"]),
    ("gear.profile_shift=0:1:3", ["gear.profile_shift", "a design result", "pair.offset_mm"]),
    ("pinion.tooth_surface=1:2:3", ["pinion.tooth_surface", "a choice key"]),
    ("pinion.cone_angle_deg=1:20:3", ["pinion.cone_angle_deg", "STOP = 20", "from -15 to 15"]),
    ("pinion.teeth=20:30:4", ["pinion.teeth", "integers"]),
    ("pinion.cone_angle_deg=1:2", ["START:STOP:COUNT"]),
    ("pinion.cone_angle_deg=1:2:0", ["COUNT = 0", "from 1 to 100000"]),
    ("pinion.cutter_addendum_coefficient=0.6:1.5:3", ["pinion.cutter_addendum_coefficient = 0.6",
                                                       "must exceed gear.addendum_coefficient"]),
])
def test_bad_vary_is_one_line_exit_2(case1, tmp_path, capsys, vary, words):
    assert main(["explore", case1, "--vary", vary, "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "Traceback" not in err
    for w in words:
        assert w in err, err


def test_bad_tolerances_and_workers(case1, tmp_path, capsys):
    assert main(["explore", case1, *GRID, "--tolerances", "dx=0.5,tilt=1", "--out", str(tmp_path / "o")]) == 2
    assert "tilt" in capsys.readouterr().err
    assert main(["explore", case1, *GRID, "--workers", "0", "--out", str(tmp_path / "o")]) == 2
    assert "--workers = 0" in capsys.readouterr().err


def test_plan_grid_and_sample():
    plan = Plan(spec_to_dict(load_example("case1")), (parse_vary("pinion.cone_angle_deg=1:3:3"),
                                                      parse_vary("pinion.teeth=20:24:3")))
    v = plan.values(0, plan.count)
    assert plan.count == 9
    assert v["pinion.cone_angle_deg"].tolist() == [1, 1, 1, 2, 2, 2, 3, 3, 3]  # the first key slowest
    assert v["pinion.teeth"].tolist() == [20, 22, 24] * 3
    sample = Plan(plan.base, plan.varies, samples=50, seed=3)
    s = sample.values(0, 50)
    assert (s["pinion.cone_angle_deg"] >= 1).all() and (s["pinion.cone_angle_deg"] <= 3).all()
    assert set(s["pinion.teeth"]) <= set(range(20, 25))
    # Latin hypercube: one sample in each of the 50 strata of every key
    assert sorted(np.floor((s["pinion.cone_angle_deg"] - 1) / 2 * 50).astype(int)) == list(range(50))
    np.testing.assert_array_equal(Plan(plan.base, plan.varies, 50, 3).values(10, 20)["pinion.cone_angle_deg"],
                                  s["pinion.cone_angle_deg"][10:20])
    with pytest.raises(UserError, match="pinion.cone_angle_deg"):
        parse_vary("pinion.cone_angle_deg=a:2:3")


def _csv(path):
    with open(path) as f:
        return list(csv.reader(f))


def test_explore_writes_rows_json_and_figures(case1, tmp_path, capsys):
    out = tmp_path / "run"
    assert main(["explore", case1, *GRID, "--workers", "1", "--out", str(out), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    table = _csv(out / "explore.csv")
    header, body = table[0], table[1:]
    assert len(body) == 9 == summary["designs"] == summary["designs_done"] and summary["complete"]
    for name in ("pinion.cone_angle_deg", "status", "working_normal_pressure_angle_deg", "fpd_angle_left_deg",
                 "gear_working_helix_angle_deg", "right_gear_angle_rad_per_vertical_rad", "worst_path_shift_mm",
                 "pareto"):
        assert name in header
    rows = summary["rows"]
    assert [r["design"] for r in rows] == list(range(9))
    front = [r for r in rows if r["pareto"]]
    assert front and len(front) == len(summary["pareto_designs"])
    ok = [r for r in rows if r["status"] == "ok"]
    for r in ok:  # nothing on the front is beaten on both objectives
        for f in front:
            assert not (r["max_fpd_angle_deg"] < f["max_fpd_angle_deg"] and r["worst_path_shift_mm"] < f["worst_path_shift_mm"])
    base = summary["base_design"]
    assert base["status"] == "ok" and abs(base["pinion_helix_angle_deg"] - 23.0) < 1e-12
    for name in ("heatmap_fpd.png", "heatmap_sensitivity.png", "pareto.png", "pareto_table.png", "pareto.csv",
                 "summary.json"):
        assert (out / name).stat().st_size > 0
    # the CSV holds the JSON rows' numbers, to the last digit
    i = header.index("worst_path_shift_mm")
    assert [float(b[i]) if b[i] else None for b in body] == [r["worst_path_shift_mm"] for r in rows]


def test_resume_computes_only_missing_chunks(case1, tmp_path, capsys):
    out = tmp_path / "run"
    assert main(["explore", case1, *GRID, "--workers", "1", "--chunk", "4", "--out", str(out)]) == 0
    full = _csv(out / "explore.csv")
    chunks = sorted(os.listdir(out / "chunks"))
    assert len(chunks) == 3
    kept = out / "chunks" / chunks[0]
    stamp = kept.stat().st_mtime_ns
    os.remove(out / "chunks" / chunks[1])
    assert main(["explore", "--resume", str(out), "--workers", "1"]) == 0
    assert kept.stat().st_mtime_ns == stamp  # not redone
    assert sorted(os.listdir(out / "chunks")) == chunks
    assert _csv(out / "explore.csv") == full
    # a different run into the same folder is refused
    assert main(["explore", case1, "--vary", "pinion.cone_angle_deg=1:2:2", "--out", str(out)]) == 2
    assert "--resume" in capsys.readouterr().err


def _as_if_made_by_another_version(out):
    path = out / "request.json"
    held = json.loads(path.read_text())
    held["code"] = {"package_version": "0.0.1", "generated_kernels_sha1": "0123456789abcdef"}
    path.write_text(json.dumps(held))


def test_chunks_of_another_version_are_recomputed_or_refused(case1, tmp_path, capsys):
    from beveloid import parallel

    out = tmp_path / "run"
    plan = Plan(spec_to_dict(load_example("case1")), (parse_vary("pinion.cone_angle_deg=1:2:2"),))
    req = runner.prepare(str(out), runner.Request(plan, {"dx_mm": 0.5}, chunk=1), resume=False)
    with parallel.executor(workers=1) as ex:
        assert runner.execute(str(out), req, ex).stop is None
    request = json.loads((out / "request.json").read_text())
    assert request["code"] == runner.code_version()
    assert request["code"]["package_version"] == beveloid.__version__
    # --resume of chunks made by another version: refused, one line saying how to go on
    _as_if_made_by_another_version(out)
    assert main(["explore", "--resume", str(out), "--workers", "1"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "beveloid 0.0.1" in err and f"--out {out}" in err
    with pytest.raises(UserError) as info:
        runner.prepare(str(out), None, resume=True)
    assert info.value.code is ErrorCode.STALE_RESULTS
    assert runner.finished(str(out), req) == [0, 1]  # nothing removed by the refusal
    # the same request again with --out: the old chunks go (then computed again, as missing ones are)
    lines = []
    again = runner.prepare(str(out), runner.Request(plan, {"dx_mm": 0.5}, chunk=1), resume=False, log=lines.append)
    assert runner.finished(str(out), again) == []
    assert len(lines) == 1 and "2 chunks of this request computed by beveloid 0.0.1" in lines[0]
    assert "computing them again" in lines[0]
    assert json.loads((out / "request.json").read_text())["code"] == runner.code_version()


class _Interrupted:
    """An executor that finishes the first two tasks (the base design and the first chunk) and then sees Ctrl-C."""

    description = "test"

    def map_unordered(self, fn, items):
        items = list(items)
        for k in range(2):
            yield k, fn(items[k])
        raise KeyboardInterrupt


def test_interrupted_run_keeps_finished_chunks(case1, tmp_path):
    out = str(tmp_path / "run")
    plan = Plan(spec_to_dict(load_example("case1")), (parse_vary("pinion.cone_angle_deg=1:3:3"),))
    req = runner.prepare(out, runner.Request(plan, {"dx_mm": 0.5}, chunk=1), resume=False)
    ran = runner.execute(out, req, _Interrupted())
    assert ran.stop is StopReason.INTERRUPTED and "Ctrl-C" in ran.why
    # the run's result: frozen, its JSON strict and naming how it ended
    with pytest.raises(dataclasses.FrozenInstanceError):
        ran.stop = None
    got = json.loads(json.dumps(ran.to_json(), allow_nan=False))
    assert got["stop"] == str(StopReason.INTERRUPTED) and got["complete"] is False and got["out_dir"] == out
    assert got["request"] == json.loads(json.dumps(req.to_json()))
    assert runner.finished(out, req) == [0]
    table = runner.load_table(out, req)
    assert table["design"].tolist() == [0]


class _Terminal:
    def __init__(self):
        self.text = ""

    def isatty(self):
        return True

    def write(self, s):
        self.text += s

    def flush(self):
        pass


def test_progress_shows_done_rate_and_time_left():
    term = _Terminal()
    p = runner.Progress(done=200, stream=term)  # the one protocol: progress(done, total, what)
    p.t0 -= 2.0  # as if 2 s had passed
    p.last -= 1.0
    p(500, 1000, "designs")
    line = term.text.strip()
    assert "500/1000 designs (50.0 %)" in line
    rate = float(line.split(",")[1].split()[0])
    assert 140 <= rate <= 150  # 300 designs in ~2 s
    assert "s left" in line
    quiet = runner.Progress(stream=open(os.devnull, "w"))
    quiet(10, 10, "designs")  # not a terminal: nothing written, nothing raised


def test_out_targets_are_refused_before_computing(case1, tmp_path, capsys, monkeypatch):
    a_file = tmp_path / "a_file"
    a_file.write_text("x")

    def boom(*a, **k):
        raise AssertionError("computed before checking --out")

    monkeypatch.setattr(runner, "execute", boom)
    for target, words in (("", "an empty name"), (str(a_file), "exists and is not a folder"),
                          (str(tmp_path / ("d" * 256)), "more than the 255")):
        assert main(["explore", case1, *GRID, "--out", target]) == 2
        err = capsys.readouterr().err.strip()
        assert "\n" not in err and "--out = " in err and words in err, err


def test_explore_and_optimize_share_one_vary_and_one_refusal():
    """One Vary (a grid with a count, a continuous range without) and one 'not a key' line for both commands."""
    from beveloid.errors import UserError
    from beveloid.explore import grid
    from beveloid.optimize import request

    assert request.Vary is grid.Vary and not hasattr(request, "_unknown_key_text")
    ranged = request.parse_vary("pinion.lead_crowning_um=0:40")
    assert (ranged.key, ranged.start, ranged.stop, ranged.count) == ("pinion.lead_crowning_um", 0.0, 40.0, None)
    assert grid.parse_vary("pinion.cone_angle_deg=1:3:3").count == 3
    lines = []
    for parse, text in ((grid.parse_vary, "pinion.no_such_key=1:2:3"), (request.parse_vary, "pinion.no_such_key=1:2")):
        with pytest.raises(UserError) as err:
            parse(text)
        lines.append(str(err.value))
    assert lines[0].replace("explore", "X").split(";")[0] == lines[1].replace("optimize", "X").split(";")[0]


def test_explore_and_optimize_keep_their_runs_in_one_store(tmp_path):
    """One RunStore: the same refusals, one line each, for an exploration's and an optimisation's folder."""
    from beveloid.errors import ErrorCode, UserError
    from beveloid.runstore import RunStore

    store = RunStore(str(tmp_path / "run"), "pieces", "pieces", "study")
    with pytest.raises(UserError, match="no request.json there"):
        store.resumed({"package_version": "1"})
    assert store.check_fresh({"a": 1, "code": {"package_version": "1"}}) is None
    store.write({"a": 1, "code": {"package_version": "1"}})
    assert (tmp_path / "run" / "pieces").is_dir() and store.held()["a"] == 1
    assert store.check_fresh({"a": 1, "code": {"package_version": "2"}}, ignore=("code",))["a"] == 1
    with pytest.raises(UserError, match="holds another study"):
        store.check_fresh({"a": 2, "code": {"package_version": "1"}})
    with pytest.raises(UserError) as err:
        store.resumed({"package_version": "2"})
    assert err.value.code is ErrorCode.STALE_RESULTS and "beveloid 1" in str(err.value)
    import inspect

    from beveloid.explore import run
    from beveloid.optimize import search
    for module in (run, search):
        assert "RunStore(" in inspect.getsource(module.prepare) and "json.dump" not in inspect.getsource(module.prepare)


def test_a_request_makes_its_solver_once():
    """Issue 56: every chunk of a run solves with the one Solver of its request (it was made anew on each
    access); a request read back from its JSON makes its own, of the same backend."""
    from beveloid.explore.grid import Plan, Vary
    from beveloid.spec import load_example, spec_to_dict

    plan = Plan(spec_to_dict(load_example("case1")), (Vary("pinion.cone_angle_deg", 1.0, 2.0, 2),))
    req = runner.Request(plan, {"dx_mm": 0.5}, backend="numpy")
    assert req.solver is req.solver and req.solver.backend == "numpy"
    again = runner.Request.from_json(req.to_json())
    assert again.solver is again.solver and again.solver == req.solver

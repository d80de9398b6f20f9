"""Same answers anywhere: one worker, local worker processes and a real Dask cluster give the same
rows (explore) and statistics (sweep) to the last digit."""
from __future__ import annotations

import json
import os

import numpy as np
import pytest

from beveloid import assembly_errors, parallel
from beveloid.cli import main
from beveloid.spec import example_text
from beveloid.sweep import DEFAULT_RANGES, draw_errors

GRID = ["--vary", "pinion.cone_angle_deg=1:3:3", "--vary", "pinion.helix_angle_deg=18:28:2", "--chunk", "2"]
#: the sweep's numbers that do not depend on where it ran (its timings do)
TIMING = ("seconds", "seconds_total", "us_per_point", "us_per_point_total")


@pytest.fixture(scope="module")
def case1(tmp_path_factory):
    path = tmp_path_factory.mktemp("spec") / "case1.toml"
    path.write_text(example_text("case1"))
    return str(path)


def _explore(case1, out, capsys, *where):
    assert main(["explore", case1, *GRID, "--mc", "4", "--mc-positions", "6", "--out", str(out), *where]) == 0
    capsys.readouterr()
    return (out / "explore.csv").read_text()


def _sweep(case1, capsys, *where):
    assert main(["sweep", case1, "--samples", "70", "--positions", "8", "--seed", "5", "--json", *where]) == 0
    out = json.loads(capsys.readouterr().out)
    return {k: v for k, v in out.items() if k not in TIMING}


def test_error_chunks_are_the_sweeps_stream():
    ranges, nominal = {"dx_mm": 0.3, "vertical_deg": 0.1}, {"dz_mm": 0.2}
    whole = draw_errors(1000, ranges, 11, nominal)
    # the whole draw is numpy's default generator of the seed (independent of the chunk arithmetic)
    half = assembly_errors.to_layout(dict(DEFAULT_RANGES, **ranges))
    expected = assembly_errors.to_layout(nominal) + np.random.default_rng(11).uniform(-1, 1, (1000, 5)) * half
    np.testing.assert_array_equal(whole, expected)
    for start, stop in ((0, 1), (0, 300), (300, 1000), (999, 1000)):
        np.testing.assert_array_equal(draw_errors(stop - start, dict(DEFAULT_RANGES, **ranges), 11, nominal,
                                                  start=start), whole[start:stop])


def test_executor_input_checks():
    from beveloid.errors import UserError

    with pytest.raises(UserError, match="give one of them"):
        parallel.executor(2, "tcp://127.0.0.1:1")
    with pytest.raises(UserError, match="--workers = 0"):
        parallel.executor(0)


@pytest.mark.slow
@pytest.mark.long_running
def test_local_workers_equal_one_worker(case1, tmp_path, capsys):
    one = _explore(case1, tmp_path / "one", capsys, "--workers", "1")
    two = _explore(case1, tmp_path / "two", capsys, "--workers", "2")
    assert one == two
    assert "mc_edge_fraction" in one.splitlines()[0]
    assert _sweep(case1, capsys, "--workers", "2") == _sweep(case1, capsys) == _sweep(case1, capsys, "--workers", "1")


@pytest.mark.slow  # a real Dask cluster (~10 s of the fast tier); .ci/run runs it
@pytest.mark.long_running
def test_dask_cluster_equals_local(case1, tmp_path, capsys, cluster):
    local = _explore(case1, tmp_path / "local", capsys, "--workers", "1")
    remote = _explore(case1, tmp_path / "dask", capsys, "--scheduler", cluster)
    assert remote == local
    summary = json.loads((tmp_path / "dask" / "summary.json").read_text())
    assert "Dask cluster" in summary["executor"] and "2 workers" in summary["executor"]
    assert _sweep(case1, capsys, "--scheduler", cluster) == _sweep(case1, capsys)


def _dies_on_two(item):
    """A chunk whose worker process dies (as a killed or crashed worker does); the others say their BLAS's
    thread count."""
    if item == 2:
        os._exit(3)
    return item * 10, os.environ.get("OPENBLAS_NUM_THREADS")


@pytest.mark.long_running
def test_lost_local_worker_keeps_what_finished_and_workers_run_one_thread(monkeypatch):
    monkeypatch.setenv("OPENBLAS_NUM_THREADS", "7")
    got = []
    with pytest.raises(parallel.WorkLost, match="died"):
        with parallel.executor(workers=2) as ex:
            for index, result in ex.map_unordered(_dies_on_two, [0, 1, 2, 3]):
                got.append((index, result))
    assert set(got) <= {(0, (0, "1")), (1, (10, "1")), (3, (30, "1"))}
    assert os.environ["OPENBLAS_NUM_THREADS"] == "7"  # this process's own setting, as it was


class _LosesWorker:
    description = "test"

    def map_unordered(self, fn, items):
        items = list(items)
        for k in range(2):  # the base design and the first chunk
            yield k, fn(items[k])
        raise parallel.WorkLost("the Dask cluster lost a chunk (KilledWorker)")


def test_run_that_loses_a_worker_keeps_its_chunks(tmp_path):
    from beveloid.errors import StopReason
    from beveloid.explore import run as runner
    from beveloid.explore.grid import Plan, parse_vary
    from beveloid.spec import load_example, spec_to_dict

    plan = Plan(spec_to_dict(load_example("case1")), (parse_vary("pinion.cone_angle_deg=1:3:3"),))
    out = str(tmp_path / "run")
    req = runner.prepare(out, runner.Request(plan, {"dx_mm": 0.5}, chunk=2), resume=False)
    ran = runner.execute(out, req, _LosesWorker())
    assert ran.stop is StopReason.WORK_LOST and "KilledWorker" in ran.why and not ran.complete
    assert runner.finished(out, req) == [0]


def test_the_broken_pool_race_after_a_ctrl_c_prints_nothing_and_other_thread_errors_still_do(monkeypatch):
    """Stopping the local workers on Ctrl-C breaks their pool; on Python 3.11 the executor's manager
    thread may then raise InvalidStateError on a cancelled future (seen: a dozen traceback lines after the
    one-line message). That error of that thread is quiet; any other thread's error is reported."""
    import concurrent.futures as cf
    import threading

    seen = []
    monkeypatch.setattr(threading, "excepthook", lambda args: seen.append((type(args.thread).__name__, args.exc_type)))
    parallel._quiet_broken_pool_race()

    class _ExecutorManagerThread(threading.Thread):  # the name of the executor's own thread class
        def run(self):
            raise cf.InvalidStateError("CANCELLED: <Future state=cancelled>")

    class Other(threading.Thread):
        def run(self):
            raise cf.InvalidStateError("a real one")

    for cls in (_ExecutorManagerThread, Other):
        t = cls()
        t.start()
        t.join()
    assert seen == [("Other", cf.InvalidStateError)]


def _nothing():
    pass


def test_a_workers_start_freezes_what_it_loaded():
    """Issue 59: after its warm-up a worker's objects (imports, numba's cache loads) are out of the collector's
    reach (gc.freeze), as the script's before its exit: its tasks' collections and its exit skip them."""
    import gc

    before = gc.get_freeze_count()
    try:
        parallel.warm_up(_nothing)
        assert gc.get_freeze_count() > before
    finally:
        gc.unfreeze()


def test_local_workers_start_when_the_executor_is_entered_and_an_error_does_not_wait_for_them():
    """Issue 59: every local worker process starts when the executor is entered (its start, imports and
    numba's cache loads, runs while the caller prepares its work), not at the first task; an error before
    any task stops them at once (the caller's one-line error is not held up by their starts), and so does
    leaving the block without handing them any.  Run in a Python of its own: the workers it starts and
    stops are that process's children, not the test runner's (a runner's worker whose children are killed
    while they start shares their stdin and stdout with its controller)."""
    import subprocess
    import sys

    code = """
import multiprocessing, sys, time
from beveloid import parallel

def stopped(processes):
    # (the pool's own thread may reap a process first: its exit code shows once that thread has it)
    deadline = time.monotonic() + 60
    while any(p.exitcode is None for p in processes) and time.monotonic() < deadline:
        time.sleep(0.01)
    return [p.exitcode for p in processes]

before = set(multiprocessing.active_children())
try:
    with parallel.executor(workers=2):
        started = set(multiprocessing.active_children()) - before
        print(len(started))
        raise ValueError("bad input")
except ValueError as exc:
    print(exc)
print(*stopped(started))
with parallel.executor(workers=2):  # no work handed out (a resumed run with nothing left): not waited for
    started = set(multiprocessing.active_children()) - before
print(len(started))
print(*stopped(started))
"""
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=600,
                       stdin=subprocess.DEVNULL)
    assert p.returncode == 0, p.stderr
    lines = p.stdout.splitlines()
    assert lines[0] == "2" and lines[1] == "bad input" and lines[3] == "2", p.stdout
    for codes in (lines[2], lines[4]):
        assert all(int(c) < 0 for c in codes.split()) and len(codes.split()) == 2, p.stdout  # killed, not finished



"""`beveloid paper`'s pieces on worker processes (beveloid/studies/tasks.py) and the FE teeth's first
computation, announced with its progress (beveloid/studies/loaded.py)."""
from __future__ import annotations

import math
import os
import re
import signal

import pytest

from beveloid.studies import loaded, tasks

#: a hang guard, not a time limit: the workers start in about a second
HANG_GUARD_S = 120


def _die():
    """A piece whose worker process is killed, as the out-of-memory killer kills it (SIGKILL)."""
    os.kill(os.getpid(), signal.SIGKILL)


def _hang(signum, frame):
    raise AssertionError(f"no answer within the hang guard ({HANG_GUARD_S} s): waiting for a lost piece")


def test_pieces_give_the_same_results_on_workers_errors_come_back_and_a_killed_worker_is_one_line(
        tmp_path, monkeypatch, capsys):
    """Pieces on two worker processes give what they give here and raise what they raise; a worker killed
    while it runs a piece (multiprocessing.Pool alone would wait for that piece forever) ends `beveloid
    paper` with one line naming the worker and its piece, exit 1, nothing written."""
    from beveloid import cli
    from beveloid.studies import paper

    def run(out, **kw):  # `beveloid paper`'s run, its pieces these
        with tasks.Tasks(2) as pool:
            far = pool.submit(math.hypot, 3.0, 4.0)
            bad = pool.submit(math.sqrt, -1.0)
            threads = pool.submit(os.getenv, "OMP_NUM_THREADS")
            assert far.get() == 5.0 == tasks.Tasks(1).submit(math.hypot, 3.0, 4.0).get()
            with pytest.raises(ValueError):
                bad.get()
            assert threads.get() == "1"  # the processes are the parallelism
            lost = pool.submit(_die)
            ran.append(True)
            lost.get()

    ran = []
    monkeypatch.setattr(paper, "run", run)
    old = signal.signal(signal.SIGALRM, _hang)
    signal.alarm(HANG_GUARD_S)
    try:
        rc = cli.main(["paper", "--out", str(tmp_path / "out")])
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)
    err = capsys.readouterr().err
    assert ran and rc == 1 and len(err.splitlines()) == 1, err
    assert re.fullmatch(r"beveloid paper: error: a worker process \(pid \d+\) was killed by SIGKILL \(as the "
                        r"out-of-memory killer does\) while running \S*test_studies_tasks\._die\(\); --out = \S+: "
                        r"nothing written \(the folder, made by this run, is removed\)\n", err), err
    assert not (tmp_path / "out").exists()


def test_the_fe_teeth_not_cached_are_submitted_each_announced_with_its_progress(tmp_path, monkeypatch, capsys):
    """A fresh cache folder: the four members' FE data are pieces of their own; each says, as it starts,
    that it is the first time, about how long it takes and that it is cached after, then its progress."""
    from beveloid.fe import cache

    monkeypatch.setenv(cache.CACHE_ENV, str(tmp_path))
    submitted = []

    class Record:
        def submit(self, fn, *args):
            submitted.append(args)

    loaded.submit_fe_teeth(Record(), ("case1", "case2"), "fe")
    assert submitted == [("case1", "pinion"), ("case1", "gear"), ("case2", "pinion"), ("case2", "gear")]
    submitted.clear()
    loaded.submit_fe_teeth(Record(), ("case1", "case2"), "plate")
    assert submitted == []

    def computed(*args, progress=None, **kw):  # the FE computation's own steps (beveloid/fe/tooth.py's protocol)
        progress(1, 2, "FE tooth pinion: meshing (refinement 1)")
        progress(2, 2, "FE tooth pinion: done in 1.0 s")
        return None, "miss"

    monkeypatch.setattr(cache, "cached_tooth_data", computed)
    how, seconds = loaded._fe_member("case1", "pinion")
    err = capsys.readouterr().err.splitlines()
    assert how == "miss" and seconds >= 0
    assert err[0] == (f"   FE tooth of the case 1 pinion: first time, about {loaded.FE_FIRST_TIME_S} s of CPU; cached"
                      f" after ({tmp_path / 'fe'})")
    assert err[1:] == ["   FE tooth of the case 1 pinion: meshing (refinement 1)",
                       "   FE tooth of the case 1 pinion: done in 1.0 s"]


def test_a_ctrl_c_while_the_workers_start_is_held_not_lost(monkeypatch):
    """SIGINT is blocked, not ignored, while the pool starts its processes: a Ctrl-C that arrives then
    interrupts as soon as they are started (ignored, it was lost and the run went on: seen as
    `paper` finishing after its Ctrl-C on a fresh install), and no worker is left behind."""
    import multiprocessing
    import multiprocessing.context

    real = multiprocessing.context.BaseContext.Pool

    def pool_then_ctrl_c(self, *args, **kwargs):
        started = real(self, *args, **kwargs)
        os.kill(os.getpid(), signal.SIGINT)  # arrives while the pool is being started
        return started

    monkeypatch.setattr(multiprocessing.context.BaseContext, "Pool", pool_then_ctrl_c)
    before = set(multiprocessing.active_children())
    with pytest.raises(KeyboardInterrupt):
        with tasks.Tasks(workers=2):
            pytest.fail("the with block ran after a Ctrl-C")
    assert not [p for p in multiprocessing.active_children() if p not in before and p.is_alive()]


_MASK_AT_START = """
import multiprocessing, signal, sys
import multiprocessing.context as context

seen = []
if sys.argv[1] == "tasks":
    def stop(self, *a, **k):  # the pool would start its workers now: the mask they would inherit
        seen.append(signal.pthread_sigmask(signal.SIG_BLOCK, set()))
        raise RuntimeError("stop")
    context.SpawnContext.Pool = stop
    from beveloid.studies.tasks import Tasks
    try:
        with Tasks(2):
            pass
    except RuntimeError:
        pass
else:
    from beveloid import parallel
    with parallel._sigint_blocked():
        multiprocessing.get_context("spawn").SimpleQueue()  # a pool's first lock starts the resource tracker
        seen.append(signal.pthread_sigmask(signal.SIG_BLOCK, set()))
print(signal.SIGINT in seen[0])
"""


@pytest.mark.parametrize("where", ["tasks", "parallel"])
def test_sigint_stays_blocked_while_the_workers_start(where):
    """issue 60: multiprocessing's resource tracker, started by the pool's first queue, unblocked SIGINT
    inside the block, so the workers of `paper` (and of --workers) took the terminal's Ctrl-C while they
    imported (6-87 lines of tracebacks).  In a fresh process (no tracker yet), SIGINT is still blocked
    when the workers start."""
    import subprocess
    import sys

    proc = subprocess.run([sys.executable, "-c", _MASK_AT_START, where], capture_output=True, text=True, timeout=120)
    assert proc.stdout.strip() == "True", proc.stderr

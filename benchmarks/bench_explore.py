"""Designs per second of `beveloid explore`: the batched path against one design at a time, and
one local worker against two.

    python benchmarks/bench_explore.py [--designs 2048] [--single 64] [--no-workers] [--tooth 256]
    python benchmarks/bench_explore.py --against CHECKOUT [--rounds 3] [--with-tooth]   # before / after in one run

Rows (status, working data, FPD angles, both flanks' sensitivities and worst path shifts; with and
without the whole-tooth checks, and their cost per checked design apart, --tooth) of case 1 with the pinion cone angle and helix angle varied over a grid that includes infeasible
designs.  The batched path is beveloid.explore.rows.compute over chunks of 256 designs in this
process; the one-design-at-a-time path is what a script does today: Pair.from_spec(spec) (design() and the
geometry) and tca.sensitivity on both flanks, for the first --single designs of the same grid
(infeasible ones cost their refused design).  Both after a warm-up (numba's cache loaded).  The
workers part runs the whole exploration (chunks, files) on 1 and on 2 local worker processes,
timed after the pools have started and loaded the compiled solver.

The part of a run outside the workers (what more workers do not make faster):

    python benchmarks/bench_explore.py --serial 200 [--against CHECKOUT] [--rounds 2]
    python benchmarks/bench_explore.py --dask 50 100 200 [--against CHECKOUT]

``--serial SIDE``: the whole `beveloid explore --workers 1` of issue 47's grid (case 1, pinion helix
angle 15-30 deg x cone angle 1-4 deg, SIDE x SIDE designs) in a fresh process of each checkout,
alternating: the wall and CPU seconds outside the workers' function (``explore.run.compute_chunk``,
timed on the side) as a fraction of the command's.  ``--dask SIDE ...``: the same command with
``--scheduler`` on a local Dask cluster of two single-threaded workers running each checkout: the
client's time before and after the chunks, and its CPU seconds, per grid.  A CHECKOUT is a folder
holding another version's tree (``git archive REV | tar -x -C DIR``), run with PYTHONPATH=DIR.
"""
from __future__ import annotations

import argparse
import sys
import tempfile
import time

import numpy as np

from beveloid import parallel, tca
from beveloid.design import DesignError
from beveloid.explore import rows
from beveloid.explore import run as runner
from beveloid.explore.grid import Plan, Vary
from beveloid.pair import Pair
from beveloid.spec import load_example, spec_to_dict
from beveloid.sweep import DEFAULT_RANGES


def _plan(n):
    side = int(round(n ** 0.5))
    return Plan(spec_to_dict(load_example("case1")), (Vary("pinion.cone_angle_deg", 0.25, 4.5, side),
                                                      Vary("pinion.helix_angle_deg", 12.0, 34.0, side)))


def batched(plan, chunk=256, tooth_checks=False):
    """Designs per second of the design and the sensitivities (rows.compute; with ``tooth_checks`` the
    whole-tooth checks too, as explore runs them; without, they are timed apart by :func:`tooth_cost`)."""
    rows.compute(plan, 0, min(chunk, plan.count), DEFAULT_RANGES, tooth_checks=tooth_checks)  # warm-up
    t, c = time.perf_counter(), time.process_time()
    ok = 0
    for s in range(0, plan.count, chunk):
        cols = rows.compute(plan, s, min(plan.count, s + chunk), DEFAULT_RANGES, tooth_checks=tooth_checks)
        ok += int((cols["status"] == "ok").sum())
    return plan.count / (time.perf_counter() - t), plan.count / (time.process_time() - c), ok


def tooth_cost(plan, count):
    """CPU ms per design that passes the design's checks of the whole-tooth checks of a row (the first
    ``count`` designs of the grid: rows.compute with minus without them)."""
    rows.compute(plan, 0, 4, DEFAULT_RANGES)  # warm-up
    c = time.process_time()
    cols = rows.compute(plan, 0, count, DEFAULT_RANGES, tooth_checks=False)
    without = time.process_time() - c
    c = time.process_time()
    cols = rows.compute(plan, 0, count, DEFAULT_RANGES)
    passed = int(np.count_nonzero(np.isin(cols["status"], ("ok", "pointed", "undercut", "tooth_check_failed"))))
    return (time.process_time() - c - without) / max(passed, 1) * 1e3, passed


def one_at_a_time(plan, count):
    values = {k: np.full(plan.count, v) for k, v in plan.base_values().items()}
    values.update(plan.values(0, plan.count))
    specs = [rows.design_spec(plan, values, j) for j in range(count)]
    t, c = time.perf_counter(), time.process_time()
    for spec in specs:
        try:
            geom = Pair.from_spec(spec).geometry  # design() and the geometry, once
        except DesignError:
            continue
        for flank in tca.FLANKS:
            tca.sensitivity(geom, flank)
    return count / (time.perf_counter() - t), count / (time.process_time() - c)


def monte_carlo(plan, count, sets=40, positions=20):
    """ms per design of the --mc sweep (sets x positions on the right flank)."""
    cols = rows.compute(plan, 0, count, DEFAULT_RANGES)
    mc = rows.MonteCarloRequest(samples=sets, positions=positions, flank="right", seed=0)
    first = {k: v[:1] for k, v in cols.items()}
    rows.monte_carlo(first, plan, slice(0, 1), DEFAULT_RANGES, mc)  # warm-up
    t = time.perf_counter()
    rows.monte_carlo(cols, plan, slice(0, count), DEFAULT_RANGES, mc)
    done = int((cols["mc_status"] == "ok").sum())
    return (time.perf_counter() - t) / max(done, 1) * 1e3, done


def _nap(seconds):
    time.sleep(seconds)
    return seconds


def _timed_chunk(task):
    """runner.compute_chunk, and the CPU seconds it took in which worker process."""
    import os

    c = time.process_time()
    cols = runner.compute_chunk(task)
    return os.getpid(), time.process_time() - c, len(cols["design"])


def workers(plan, n):
    """(designs/s wall of the whole exploration, CPU seconds per worker process of the same chunks)."""
    req = runner.Request(plan, dict(DEFAULT_RANGES), chunk=128)
    with parallel.executor(workers=n, initializer=runner.warm_up) as ex:
        list(ex.map_unordered(_nap, [1.0] * n))  # the pool's processes started and warmed up
        with tempfile.TemporaryDirectory() as out:
            runner.prepare(out, req, resume=False)
            t = time.perf_counter()
            stop = runner.execute(out, req, ex).stop
            assert stop is None
            rate = plan.count / (time.perf_counter() - t)
        cpu = {}
        tasks = [runner.ChunkTask(req.to_json(), i) for i in range(req.chunks)]
        for _, (pid, seconds, _) in ex.map_unordered(_timed_chunk, tasks):
            cpu[pid] = cpu.get(pid, 0.0) + seconds
    return rate, cpu


_BATCHED = ("import os, sys; sys.path[:0] = [os.getcwd(), os.path.join(os.getcwd(), 'benchmarks')];"
            " from bench_explore import _plan, batched; r = batched(_plan({designs})); print(r[0], r[1])")
#: the same timing with explore's whole-tooth checks, written here (not imported from the other checkout,
#: whose benchmark may predate the option): the rows of the grid of _plan, chunks of 256
_WITH_TOOTH = """
import os, sys, time
sys.path[:0] = [os.getcwd()]
from beveloid.explore import rows
from beveloid.explore.grid import Plan, Vary
from beveloid.spec import load_example, spec_to_dict
from beveloid.sweep import DEFAULT_RANGES
side = int(round({designs} ** 0.5))
plan = Plan(spec_to_dict(load_example("case1")), (Vary("pinion.cone_angle_deg", 0.25, 4.5, side),
                                                  Vary("pinion.helix_angle_deg", 12.0, 34.0, side)))
rows.compute(plan, 0, 256, DEFAULT_RANGES)
t, c = time.perf_counter(), time.process_time()
for s in range(0, plan.count, 256):
    rows.compute(plan, s, min(plan.count, s + 256), DEFAULT_RANGES)
print(plan.count / (time.perf_counter() - t), plan.count / (time.process_time() - c))
"""


def against(other: str, rounds: int, designs: int, with_tooth: bool = False) -> None:
    """:func:`batched` of another checkout (``other``, e.g. a worktree of the commit before a change) and of
    this one, alternating in one run, each in a fresh process (its own beveloid); the ratios after/before.
    ``with_tooth``: the rows with explore's whole-tooth checks (:data:`_WITH_TOOTH`)."""
    import os
    import subprocess

    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    runs = {"before": [], "after": []}
    code = (_WITH_TOOTH if with_tooth else _BATCHED).format(designs=designs)
    for i in range(rounds):
        for label, where in (("before", other), ("after", here)):
            out = subprocess.run([sys.executable, "-c", code], cwd=where, check=True,
                                 capture_output=True, text=True).stdout.split()
            runs[label].append((float(out[-2]), float(out[-1])))
            print(f"round {i + 1} {label:6} ({where}): {runs[label][-1][0]:6.0f} designs/s wall,"
                  f" {runs[label][-1][1]:6.0f} per CPU second (load {os.getloadavg()[0]:.1f})", flush=True)
    for k, what in ((0, "wall"), (1, "CPU")):
        ratios = [a[k] / b[k] for a, b in zip(runs["after"], runs["before"])]
        print(f"after / before, {what}: " + ", ".join(f"{r:.3f}" for r in ratios)
              + f"; mean {np.mean(ratios):.3f}")


#: the whole command in a fresh process of a checkout (the working directory), with the time inside the
#: workers' function (compute_chunk: a worker's part of the run) summed on the side and runner.execute (the
#: run of the chunks) timed: prints the exit status, then wall seconds of the command, inside compute_chunk,
#: before execute and after it, then the CPU seconds of the process and inside compute_chunk
_SERIAL = r"""
import os, sys, tempfile, time
sys.path.insert(0, os.getcwd())
from beveloid.cli import main
from beveloid.explore import run as runner
spent = {"chunks": 0.0, "chunks_cpu": 0.0}
chunk, execute = runner.compute_chunk, runner.execute

def timed_chunk(*a, **k):
    t, c = time.perf_counter(), time.process_time()
    try:
        return chunk(*a, **k)
    finally:
        spent["chunks"] += time.perf_counter() - t
        spent["chunks_cpu"] += time.process_time() - c

def timed_execute(*a, **k):
    spent["execute_start"] = time.perf_counter()
    try:
        return execute(*a, **k)
    finally:
        spent["execute_end"] = time.perf_counter()

runner.compute_chunk = timed_chunk  # looked up by execute at each call
runner.execute = timed_execute
with tempfile.TemporaryDirectory() as tmp:
    t, c = time.perf_counter(), time.process_time()
    rc = main(["explore", "examples/case1.toml", *sys.argv[1:], "--out", os.path.join(tmp, "run")])
    end, cpu = time.perf_counter(), time.process_time() - c
    print(rc, end - t, spent["chunks"], spent["execute_start"] - t, end - spent["execute_end"], cpu,
          spent["chunks_cpu"])
"""


def _grid_args(side: int) -> list[str]:
    """Issue 47's grid: case 1, pinion helix angle 15-30 deg x cone angle 1-4 deg, side x side designs."""
    return ["--vary", f"pinion.helix_angle_deg=15:30:{side}", "--vary", f"pinion.cone_angle_deg=1:4:{side}"]


def _command(where: str, argv: list[str]) -> list[float]:
    import os
    import subprocess

    env = dict(os.environ, PYTHONPATH=where)
    out = subprocess.run([sys.executable, "-c", _SERIAL, *argv], cwd=where, env=env, check=True,
                         capture_output=True, text=True).stdout.split()
    return [float(x) for x in out[-7:]]


def serial(checkouts: dict, side: int, rounds: int) -> None:
    """The part of `beveloid explore --workers 1` outside the workers' function (reading the spec,
    saving the chunks, the base design where the main process computes it, the files and figures) as a
    fraction of the whole command, for each checkout (label -> folder), alternating, each run in a
    fresh process."""
    import os

    for label, where in checkouts.items():  # numba's caches of each checkout loaded once before timing
        _command(where, [*_grid_args(2), "--workers", "1"])
    for r in range(rounds):
        for label, where in checkouts.items():
            rc, total, chunks, _, after, cpu, chunks_cpu = _command(where, [*_grid_args(side), "--workers", "1"])
            assert rc == 0
            outside, outside_cpu = total - chunks, cpu - chunks_cpu
            print(f"round {r + 1} {label:6} ({where}): {side * side} designs, --workers 1: {total:6.2f} s,"
                  f" outside the workers' function {outside:5.2f} s = {100 * outside / total:4.1f} % (after the"
                  f" chunks {after:5.2f} s); CPU {cpu:6.2f} s, outside {outside_cpu:5.2f} s ="
                  f" {100 * outside_cpu / cpu:4.1f} % (load {os.getloadavg()[0]:.1f})", flush=True)


class _Cluster:
    """A Dask scheduler and ``workers`` single-threaded workers on 127.0.0.1, running a checkout's code."""

    def __init__(self, where: str, workers: int):
        import os
        import socket
        import subprocess

        with socket.socket() as s:
            s.bind(("127.0.0.1", 0))
            port = s.getsockname()[1]
        self.address = f"tcp://127.0.0.1:{port}"
        env = dict(os.environ, PYTHONPATH=where)
        self.log = open(os.devnull, "w")  # noqa: SIM115
        run = [sys.executable, "-m"]
        self.procs = [subprocess.Popen(run + ["distributed.cli.dask_scheduler", "--host", "127.0.0.1", "--port",
                                              str(port), "--dashboard-address", ":0"], cwd=where, env=env,
                                       stdout=self.log, stderr=self.log)]
        self.procs += [subprocess.Popen(run + ["distributed.cli.dask_worker", self.address, "--nthreads", "1",
                                               "--no-nanny", "--dashboard-address", ":0"], cwd=where, env=env,
                                        stdout=self.log, stderr=self.log) for _ in range(workers)]
        from distributed import Client

        deadline = time.monotonic() + 120
        while True:
            try:
                with Client(self.address, timeout="5s") as client:
                    client.wait_for_workers(workers, timeout=max(1.0, deadline - time.monotonic()))
                return
            except (OSError, TimeoutError):
                if time.monotonic() > deadline:
                    raise
                time.sleep(0.5)

    def close(self):
        for p in self.procs[::-1]:
            p.terminate()
            p.wait(timeout=10)
        self.log.close()


def dask_client(checkouts: dict, sides: list[int], workers: int) -> None:
    """`beveloid explore --scheduler` on a local cluster of ``workers`` single-threaded workers running each
    checkout, per grid: the client's time before the chunks (its start, connecting to the cluster) and after
    them (the outputs), as a fraction of the command's time; and the client's CPU seconds in all."""
    import os

    for label, where in checkouts.items():
        cluster = _Cluster(where, workers)
        try:
            _command(where, [*_grid_args(2), "--scheduler", cluster.address])  # every worker warmed up
            for side in sides:
                rc, total, _, before, after, cpu, _ = _command(where, [*_grid_args(side), "--scheduler",
                                                                       cluster.address])
                assert rc == 0
                print(f"{label:6} ({where}): {side * side:6d} designs on {workers} Dask workers: {total:6.2f} s,"
                      f" the client before the chunks {before:5.2f} s and after them {after:5.2f} s"
                      f" ({100 * after / total:4.1f} %), the client's CPU {cpu:6.2f} s ({100 * cpu / total:4.1f} %"
                      f" of the command's time; load {os.getloadavg()[0]:.1f})", flush=True)
        finally:
            cluster.close()


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--designs", type=int, default=2048)
    ap.add_argument("--single", type=int, default=64)
    ap.add_argument("--no-workers", action="store_true")
    ap.add_argument("--tooth", type=int, default=256, metavar="N",
                    help="time the whole-tooth checks on the first N designs (0: not)")
    ap.add_argument("--against", metavar="CHECKOUT",
                    help="only: the batched rate of CHECKOUT (before) and of this checkout (after), alternating")
    ap.add_argument("--rounds", type=int, default=3, help="with --against: alternations (default 3)")
    ap.add_argument("--with-tooth", action="store_true",
                    help="with --against: the rows with the whole-tooth checks, as explore computes them")
    ap.add_argument("--serial", type=int, metavar="SIDE",
                    help="only: the time of `beveloid explore --workers 1` outside the workers on issue 47's grid"
                         " of SIDE x SIDE designs (with --against: CHECKOUT and this checkout, --rounds times)")
    ap.add_argument("--dask", type=int, nargs="+", metavar="SIDE",
                    help="only: the client's share of `beveloid explore --scheduler` on a local cluster of two"
                         " workers, on grids of SIDE x SIDE designs (with --against: CHECKOUT too)")
    a = ap.parse_args(argv)
    import os

    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    checkouts = dict(({"before": a.against} if a.against else {}), after=here)
    if a.serial:
        serial(checkouts, a.serial, a.rounds)
        return 0
    if a.dask:
        dask_client(checkouts, a.dask, workers=2)
        return 0
    if a.against:
        against(a.against, a.rounds, a.designs, a.with_tooth)
        return 0
    plan = _plan(a.designs)
    print(f"load average before: {os.getloadavg()[0]:.1f} (2 cores)")
    rate, cpu_rate, ok = batched(plan)
    single, cpu_single = one_at_a_time(plan, a.single)
    print(f"grid: {plan.count} designs of case 1 ({ok} ok), pinion cone x helix angle")
    print(f"batched design + sensitivities (rows.compute, chunks of 256, 1 process, no whole-tooth checks):"
          f"  {rate:8.0f} designs/s wall, {cpu_rate:8.0f} per CPU second")
    print(f"one at a time (Pair.from_spec + 2 x tca.sensitivity, first {a.single}): {single:8.0f} designs/s wall,"
          f" {cpu_single:8.0f} per CPU second")
    print(f"speed-up of the batched path: {rate / single:.1f}x wall, {cpu_rate / cpu_single:.1f}x CPU")
    rate_t, cpu_rate_t, ok_t = batched(plan, tooth_checks=True)
    print(f"batched with the whole-tooth checks (rows as explore writes them, {ok_t} ok):"
          f" {rate_t:8.0f} designs/s wall, {cpu_rate_t:8.0f} per CPU second ({cpu_rate_t / cpu_rate:.2f}x without)")
    if a.tooth:
        ms_tooth, passed = tooth_cost(plan, a.tooth)
        print(f"whole-tooth checks (undercut, tip; first {a.tooth} designs, {passed} pass the design's checks):"
              f" {ms_tooth:.3f} CPU ms per design checked, {1e3 / ms_tooth:.0f} designs/s")
    ms, done = monte_carlo(plan, 16)
    print(f"--mc 40 --mc-positions 20: {ms:.0f} ms per design ({done} designs)")
    if not a.no_workers:
        w1, cpu1 = workers(plan, 1)
        w2, cpu2 = workers(plan, 2)
        print(f"explore on 1 local worker:  {w1:8.0f} designs/s wall")
        print(f"explore on 2 local workers: {w2:8.0f} designs/s wall ({w2 / w1:.2f}x one worker)")
        # CPU seconds of the same chunks: their sum shows the parallel overhead, the busiest worker the
        # wall time two free cores would need
        one, two = sum(cpu1.values()), sum(cpu2.values())
        print(f"CPU seconds of the chunks: 1 worker {one:.2f}; 2 workers {two:.2f} in all"
              f" ({', '.join(f'{v:.2f}' for v in cpu2.values())}): {one / max(cpu2.values()):.2f}x on two free cores")
        print(f"load average after: {os.getloadavg()[0]:.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

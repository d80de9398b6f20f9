"""The serial part of each parallel command: the time outside its workers' parallel section, as a share of
a one-worker run, and the speed-up it allows on 16 workers (Amdahl).

    python benchmarks/bench_serial_share.py [explore sweep ltca optimize] [--budget 128] [--rounds 1]

Not a test.  Each command runs as its own process (start-up, imports and numba's cache loads count) with
one worker: ``--workers 1`` (this process: ``beveloid.parallel``'s serial executor) for explore, ltca
and optimize, ``NUMBA_NUM_THREADS=1`` for sweep.  Inside the parallel section: the time of the function
the workers run, timed around each call in the command's process (explore ``explore.run.compute_chunk``,
ltca ``ltca.studies._task``: its chunks and the analyses at the file's errors, optimize
``optimize.search.evaluate_task``), and for sweep its own
``seconds`` (the error sets solved on the threads, ``SweepResult.seconds``; its CPU: the CPU of its pieces,
``sweep._solve_sets``, those of the warm-up's small sweep left out).  Outside (serial): the rest
of the command's wall time: start-up, reading the spec, set-up, gathering, writing, figures.

explore's figures are tasks of its executor too (``explore.report.draw_figure``, one per figure, drawn by
the workers while the command writes its data files): timed apart (F), they are neither outside nor
divided by W, as they run on at most as many workers as there are figures.

The projection for W workers: T_W = S + U + M_W + F_W, T_1 = S + P + F (S outside, P inside, wall seconds);
M_W the tasks' makespan on W workers (each takes the next task in order as soon as it is free: with fewer
or uneven tasks it exceeds P / W; sweep's one section of many pieces on threads: P / W) and U what every
worker pays again before its first task that the one-worker run counts inside P: the start of a worker
process (a fresh Python's imports and numba's cache loads, measured here by a process that runs
``beveloid.parallel.warm_up`` with the command's initializer, its exit included; the one-worker run's first
task paid it too: its excess over the median task is taken off it) and, for optimize, that excess (the FE
data read in the worker); for ltca, whose first task (the file's errors) is smaller than the others, a
fresh process that starts so and then analyses the pair at one position (the LTCA's imports and cache
loads, the FE data read: ``LTCA_FIRST``; what it takes more than a bare start is taken off the one-worker
run's first task, which paid it too); U = 0 for sweep (threads of one process).  Local workers start when the
command enters its executor (``beveloid.parallel``), so the part of U that a worker does in its start (its
imports, numba's loads, its initializer: all of explore's; optimize's and ltca's but what their first task
loads) runs while the command itself works towards its first task (optimize: its baseline): O, the
command's own time from entering the executor to handing it the first task in the one-worker run, is taken
off it: U = max(0, U_start - O) + U_first. F_W: the figure tasks on W
workers (W >= 4: the longest one plus matplotlib's import, measured in a fresh process, which each of those
workers pays; the one-worker run paid it once), less the time the command writes its data files meanwhile
(``explore.report.write_data``, timed: part of S, done while the workers draw). Speed-up T_1 / T_W.

The projection is made twice: from wall seconds, and from CPU seconds (each process's own, each timed
call's ``time.process_time``): on a machine shared with other work the CPU figure is the steadier
estimate of a quiet machine on which every worker has a core of its own.

The commands (case 1 from ``beveloid example``; ltca and optimize on it tilted by vertical_deg = 0.05,
docs/optimize.md's spec, FE tooth, FE data cached by a warm-up run):

* explore: ``--vary pinion.helix_angle_deg=15:30:200 --vary pinion.cone_angle_deg=1:4:200`` (40,000 designs);
* sweep: ``--samples 64000 --positions 50`` (3.2 M points) ``--json``;
* ltca: ``--torque-nm 100,200,400 --samples 64 --json``;
* optimize: ``--vary pinion.lead_crowning_um=0:40 --vary pinion.lead_slope_um=-30:30 --torque-nm
  100,200,400 --weights 0.2,0.5,0.3 --samples 16 --tooth-model fe --budget B`` (docs/optimize.md
  section 6; ``--budget`` here, default 128).
"""
from __future__ import annotations

import argparse
import heapq
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

_CHILD = r"""
import json, os, sys, tempfile, time
t_start = time.perf_counter()
from beveloid.cli import main
kind, argv = sys.argv[1], sys.argv[2:]
took, figures, writes = [], [], []
if kind != "sweep":
    import importlib
    timed_fns = {"explore": [("beveloid.explore.run", "compute_chunk", took),
                             ("beveloid.explore.report", "draw_figure", figures),
                             ("beveloid.explore.report", "write_data", writes)],
                 "ltca": [("beveloid.ltca.studies", "_task", took)],
                 "optimize": [("beveloid.optimize.search", "evaluate_task", took)]}[kind]
    def timing(fn, into):
        def timed(*a, **k):
            t, c = time.perf_counter(), time.process_time()
            try:
                return fn(*a, **k)
            finally:
                into.append((time.perf_counter() - t, time.process_time() - c))
        return timed
    for module, name, into in timed_fns:
        mod = importlib.import_module(module)
        setattr(mod, name, timing(getattr(mod, name), into))  # looked up by the command at each call
    # when the command enters its executor (where local workers start) and first hands it tasks
    from beveloid import parallel
    marks = {}
    def first(name, fn):
        def marked(*a, **k):
            marks.setdefault(name, (time.perf_counter(), time.process_time()))
            return fn(*a, **k)
        return marked
    parallel._Serial.__enter__ = first("enter", parallel._Serial.__enter__)
    parallel._Serial.map_unordered = first("submit", parallel._Serial.map_unordered)
if kind == "sweep":  # the solve's CPU: its pieces (on one thread: in this thread, in order), the warm-up's not
    import beveloid.sweep as sw, beveloid.cli.sweep as cs
    solving, warming = [], []
    def warm(fn):
        def warmed(*a, **k):
            warming.append(1)
            try:
                return fn(*a, **k)
            finally:
                warming.pop()
        return warmed
    def piece(fn):
        def timed(*a, **k):
            c = time.process_time()
            try:
                return fn(*a, **k)
            finally:
                if not warming:
                    solving.append(time.process_time() - c)
        return timed
    cs._warm_up, sw._solve_sets = warm(cs._warm_up), piece(sw._solve_sets)  # looked up at each call
import contextlib, io
buf = io.StringIO()
sys.argv = ["beveloid", *argv]  # main() as the script calls it: its collector settings and gc.freeze before the exit
with contextlib.redirect_stdout(buf):
    rc = main()
out = buf.getvalue()
if kind == "sweep":
    took.append((json.loads(out)["seconds"], sum(solving)))
overlap = [0.0, 0.0]
if kind != "sweep" and "enter" in marks and "submit" in marks:
    overlap = [b - a for a, b in zip(marks["enter"], marks["submit"])]
print(json.dumps({"rc": rc, "took": took, "figures": figures, "in_process": time.perf_counter() - t_start,
                  "overlap": overlap, "writes": [sum(w[i] for w in writes) for i in (0, 1)]}))
"""


def spec(tmp: Path, tilted: bool) -> str:
    text = subprocess.run([sys.executable, "-m", "beveloid.cli", "example", "case1"], capture_output=True,
                          text=True, check=True).stdout
    if tilted:
        text = text.replace("vertical_deg = 0.0 ", "vertical_deg = 0.05", 1)
    path = tmp / ("case1_tilted.toml" if tilted else "case1.toml")
    path.write_text(text)
    return str(path)


def commands(tmp: Path, budget: int) -> dict:
    case1, tilted = spec(tmp, False), spec(tmp, True)
    return {
        "explore": ["explore", case1, "--vary", "pinion.helix_angle_deg=15:30:200", "--vary",
                    "pinion.cone_angle_deg=1:4:200", "--workers", "1", "--out", str(tmp / "explore")],
        "sweep": ["sweep", case1, "--samples", "64000", "--positions", "50", "--json"],
        "ltca": ["ltca", tilted, "--torque-nm", "100,200,400", "--samples", "64", "--workers", "1", "--json"],
        "optimize": ["optimize", tilted, "--vary", "pinion.lead_crowning_um=0:40", "--vary",
                     "pinion.lead_slope_um=-30:30", "--torque-nm", "100,200,400", "--weights", "0.2,0.5,0.3",
                     "--samples", "16", "--tooth-model", "fe", "--budget", str(budget), "--workers", "1",
                     "--out", str(tmp / "optimize")],
    }


def small(kind: str, argv: list) -> list:
    """A small run of the same command (its warm-up: numba's cache, the FE data of the tilted pair)."""
    small = list(argv)
    if kind == "ltca":
        small[small.index("--samples") + 1] = "8"
    if kind == "optimize":
        small[small.index("--budget") + 1] = "2"
    if kind == "explore":
        small[2:6] = ["--vary", "pinion.helix_angle_deg=15:30:3", "--vary", "pinion.cone_angle_deg=1:4:3"]
    if kind == "sweep":
        small[small.index("--samples") + 1] = "4"
    return small


def child(kind: str, argv: list) -> dict:
    env = dict(os.environ)
    env.update({"NUMBA_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1",
                "OPENBLAS_NUM_THREADS": "1", "PYTHONPATH": str(ROOT)})
    t, before = time.perf_counter(), os.times()
    proc = subprocess.run([sys.executable, "-c", _CHILD, kind, *argv], capture_output=True, text=True, env=env,
                          cwd=tempfile.gettempdir())
    wall, after = time.perf_counter() - t, os.times()
    if proc.returncode != 0:
        raise SystemExit(f"{kind}: exited {proc.returncode}:\n{proc.stderr[-3000:]}")
    out = json.loads(proc.stdout.strip().splitlines()[-1])
    out["wall"] = wall
    out["cpu"] = (after.children_user - before.children_user) + (after.children_system - before.children_system)
    return out


#: the initializer each command gives its local workers (beveloid.parallel.executor's ``initializer``)
INITIALIZERS = {"explore": "beveloid.explore.run:warm_up"}
#: what a worker of ltca --samples does before its first task's own work, as a fresh process does it: its
#: start, then a one-position analysis of the pair (the LTCA's imports and cache loads, the FE data read)
LTCA_FIRST = ("from beveloid import ltca; from beveloid.ltca import studies; from beveloid.pair import Pair;"
              " from beveloid.spec import load_spec; studies._task(('box', Pair.from_spec(load_spec({spec!r})),"
              " ltca.LoadCase([100.0]), ltca.Options(positions=1)))")


def worker_start(initializer: str | None = None, then: str = "") -> tuple[float, float]:
    """(wall, CPU) seconds of a fresh process that starts as a local worker does (beveloid.parallel.warm_up with the
    command's ``initializer``, "module:function"), then runs ``then``, its exit included."""
    code = "from beveloid import parallel; parallel.warm_up()"
    if initializer:
        module, name = initializer.split(":")
        code = f"from beveloid import parallel; from {module} import {name}; parallel.warm_up({name})"
    code += f"; {then}" if then else ""
    return _timed(code)


def _timed(code: str) -> tuple[float, float]:
    """(wall, CPU) seconds of a fresh Python running ``code``."""
    t, before = time.perf_counter(), os.times()
    subprocess.run([sys.executable, "-c", code], check=True, env=dict(os.environ, PYTHONPATH=str(ROOT)),
                   cwd=tempfile.gettempdir())
    after = os.times()
    return (time.perf_counter() - t,
            (after.children_user - before.children_user) + (after.children_system - before.children_system))


_TINY = """import numba


@numba.njit(cache=True)
def one(x):
    return x + 1.0
"""


def floor(tmp: Path) -> tuple[float, float]:
    """(wall, CPU) seconds of a fresh Python that imports numpy and numba and calls one compiled function from
    numba's cache (its first call sets up numba's compiler context, which imports scipy.linalg for its BLAS
    check): what any process that runs compiled code pays, a local worker or sweep's own."""
    (tmp / "floor_tiny.py").write_text(_TINY)
    code = f"import sys; sys.path.insert(0, {str(tmp)!r}); import numpy, floor_tiny; floor_tiny.one(1.0)"
    _timed(code)  # (compiles it into the cache)
    return _timed(code)


def load_average() -> float:
    """The load average of the last minute (nan where the system gives none)."""
    try:
        return os.getloadavg()[0]
    except OSError:
        return float("nan")


def makespan(tasks: list, workers: int) -> float:
    """Seconds until the last of ``tasks`` (seconds each, in the order they are handed out) ends on ``workers``
    workers that each take the next task as soon as they are free (a process pool's queue)."""
    free = [0.0] * workers
    for t in tasks:
        heapq.heapreplace(free, free[0] + t)
    return max(free)


def figures_start() -> tuple[float, float]:
    """(wall, CPU) seconds of matplotlib's import in a fresh process (what each worker that draws a figure pays
    once), less a bare Python's start."""
    bare, mpl = _timed("pass"), _timed("import matplotlib.figure, matplotlib.backends.backend_agg")
    return max(0.0, mpl[0] - bare[0]), max(0.0, mpl[1] - bare[1])


def project(kind: str, tasks: list, figs: list, S: float, start: float, loads: float, mpl: float, W: int,
            overlap: float = 0.0, writes: float = 0.0) -> dict:
    """The projection on W workers of a one-worker run (seconds of one kind: wall or CPU): ``tasks`` and ``figs``
    the timed calls in order, ``S`` outside, ``start`` a worker's measured start, ``loads`` (ltca) what the
    first task loaded, ``mpl`` matplotlib's import, ``overlap`` the command's own work between entering its
    executor (where local workers start) and handing it the first task, ``writes`` (explore) what it does
    while its workers draw the figures (its data files)."""
    tasks = list(tasks)
    # what the one-worker run loaded in its first task a worker loads before its first: in its initializer
    # (then in its measured start) or in its first task (then this excess)
    first = max(0.0, tasks[0] - statistics.median(tasks)) if len(tasks) > 2 else 0.0
    if kind == "ltca":  # the loads of the one-worker run's first task, measured apart
        first = min(loads, tasks[0])
    tasks[0] -= first  # (each worker pays it before its first task: in U)
    # a worker's start (its initializer included) runs while the command works towards its first task; what a
    # worker loads in its first task (optimize's excess, ltca's loads) waits for that task
    early, late = {"explore": (start, 0.0), "optimize": (start, first), "ltca": (start - loads, loads)}.get(
        kind, (0.0, 0.0))
    U = max(0.0, early - overlap) + late
    # the figures, one task each, at once on min(W, figures) workers: each of those workers imports matplotlib
    # (the one-worker run paid it once, in its first figure)
    FW = 0.0
    if figs:
        imp = min(mpl, figs[0])
        draws = sorted([figs[0] - imp] + figs[1:], reverse=True)
        FW = imp + sum(draws[::min(W, len(draws))])  # (W >= figures: the longest)
        FW = max(0.0, FW - writes)  # the command writes its data files (in S) while they draw
    # sweep: its one timed section is many pieces on threads (benchmarks/bench_sweep_threads.py)
    M = sum(tasks) / W if kind == "sweep" else makespan(tasks, W)
    return {"U": U, "M": M, "FW": FW, "TW": S + U + M + FW, "tasks": tasks}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("kinds", nargs="*", default=["explore", "sweep", "ltca", "optimize"])
    ap.add_argument("--budget", type=int, default=128, help="optimize's candidates (default 128)")
    ap.add_argument("--rounds", type=int, default=1)
    ap.add_argument("--workers", type=int, default=16, help="the projection's workers (default 16)")
    a = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="serial_") as tmp_name:
        tmp = Path(tmp_name)
        cmds = commands(tmp, a.budget)
        starts, loads = {}, (0.0, 0.0)
        mpl = figures_start() if "explore" in a.kinds else (0.0, 0.0)
        print(f"load average {load_average():.1f}", flush=True)
        base = floor(tmp)
        print(f"a process's floor (Python, numpy, numba and one function from numba's cache): {base[0]:.2f} s wall,"
              f" {base[1]:.2f} s CPU", flush=True)
        for kind in a.kinds:
            child(kind, small(kind, cmds[kind]))  # a small run first: numba's cache (and the FE data of the tilted pair)
            if kind in ("explore", "optimize"):  # (after the small run: numba's cache is on disk)
                starts[kind] = worker_start(INITIALIZERS.get(kind))
            if kind == "ltca":  # (after the small run: the FE data is on disk, as for the command's workers)
                starts[kind] = worker_start(then=LTCA_FIRST.format(spec=cmds[kind][1]))
                bare = worker_start()
                loads = tuple(max(0.0, x - y) for x, y in zip(starts[kind], bare))  # the LTCA's loads, FE data read
            for r in range(a.rounds):
                for path in tmp.glob("*/"):
                    subprocess.run(["rm", "-rf", str(path)], check=True)
                res = child(kind, cmds[kind])
                start = starts.get(kind, (0.0, 0.0))
                tasks = [w for w, _ in res["took"]]
                figs = [w for w, _ in res["figures"]]
                P, F = sum(tasks), sum(figs)
                T1 = res["wall"]
                S = T1 - P - F
                overlap = res.get("overlap", [0.0, 0.0])
                writes = res.get("writes", [0.0, 0.0])
                wall = project(kind, tasks, figs, S, start[0], loads[0], mpl[0], a.workers, overlap[0], writes[0])
                cpu = res["cpu"]
                c_tasks, c_figs = [c for _, c in res["took"]], [c for _, c in res["figures"]]
                S_cpu = cpu - sum(c_tasks) - sum(c_figs)
                by_cpu = project(kind, c_tasks, c_figs, S_cpu, start[1], loads[1], mpl[1], a.workers, overlap[1],
                                 writes[1])
                cpu_text = (f"CPU: {cpu:.2f} s, outside {S_cpu:.2f} s = {100 * S_cpu / cpu:.1f} %, a worker's start"
                            f" {start[1]:.2f} s ({by_cpu['U']:.2f} s of it not behind the command's own work of"
                            f" {overlap[1]:.2f} s meanwhile), the tasks on {a.workers} workers {by_cpu['M']:.2f} s, the"
                            f" figures {by_cpu['FW']:.2f} s; projected {by_cpu['TW']:.2f} s, speed-up"
                            f" {cpu / by_cpu['TW']:.1f}x")
                fig_text = (f", in the figure tasks {F:.2f} s ({len(figs)}; on {a.workers} workers {wall['FW']:.2f} s"
                            f" more than the data files' {writes[0]:.2f} s written meanwhile, with matplotlib's import"
                            f" {mpl[0]:.2f} s)" if figs else "")
                print(f"{kind} (round {r + 1}): one worker {T1:.2f} s wall, inside the workers' function "
                      f"{P:.2f} s ({len(tasks)} calls; on {a.workers} workers {wall['M']:.2f} s)"
                      f"{fig_text}, outside {S:.2f} s = {100 * S / T1:.1f} %; each worker's "
                      f"start {start[0]:.2f} s ({wall['U']:.2f} s of it not behind the command's own work of"
                      f" {overlap[0]:.2f} s meanwhile); projected on {a.workers} workers {wall['TW']:.2f} s, speed-up"
                      f" {T1 / wall['TW']:.1f}x (load {load_average():.1f})", flush=True)
                print(f"  the same in {cpu_text}", flush=True)
                tasks = wall["tasks"]
                print(f"  tasks (s, wall; the first less its loads): first {tasks[0]:.2f}, median"
                      f" {statistics.median(tasks):.2f}, largest"
                      f" {max(tasks):.2f} (task {tasks.index(max(tasks))} of {len(tasks)})", flush=True)
                print(f"  command: beveloid {' '.join(Path(x).name if x.startswith(str(tmp)) else x for x in cmds[kind])}",
                      flush=True)


if __name__ == "__main__":
    main()

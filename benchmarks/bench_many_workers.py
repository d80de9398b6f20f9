"""Many workers measured, not projected: each parallel command's wall time with one worker and with W workers,
in one run, on the machine it runs on (a many-core one: issue 59's 16 workers).

    python benchmarks/bench_many_workers.py [explore sweep ltca optimize] [--workers W] [--rounds 2]
        [--budget 128] [--tooth-model fe|plate] [--json FILE]
    python benchmarks/bench_many_workers.py starts [--workers W] [--rounds 3]

Not a test.  The commands are ``benchmarks/bench_serial_share.py``'s (the same arguments, the same small run of
each first: numba's cache, the FE data), each run as its own process as a user runs it (``python -m beveloid.cli``
with the tree of this script first on PYTHONPATH): with one worker (``--workers 1``; sweep
``NUMBA_NUM_THREADS=1``; both with one BLAS and OpenMP thread, as bench_serial_share.py runs them), then with W
(``--workers W``; sweep ``NUMBA_NUM_THREADS=W``; the environment otherwise as it is), alternating, ``--rounds``
times.  Printed per run: wall seconds and the CPU seconds of the command's process and its children (a local
worker's CPU counts once it has exited); then per command the least wall time of each and the speed-up
T_1 / T_W, beside the Amdahl bound of that speed-up for the serial share bench_serial_share.py measures
(run it on the same machine for its projection).  ``--tooth-model`` replaces the LTCA's tooth model of the ltca
and optimize commands (``plate`` on a machine without gmsh: the default is then the plate anyway).

``starts``: where a process's start goes on this machine: fresh Pythons that import numpy, numpy and
scipy.linalg, numpy and numba, and that start as explore's local worker does (``beveloid.parallel.warm_up`` with
explore's initializer), each with the environment as it is and with one BLAS and OpenMP thread, alternating
(the least of ``--rounds`` of each, wall and CPU); then 1, 4 and W such worker starts at once (one thread each,
as ``beveloid.parallel`` starts its workers): the wall time until the last has exited.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_serial_share import ROOT, commands, load_average, small  # noqa: E402  (one definition of the commands)

ONE_THREAD = {"NUMBA_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"}


def with_workers(kind: str, argv: list, workers: int) -> tuple[list, dict]:
    """(Python's arguments, environment) of ``kind``'s command with ``workers`` workers (sweep: numba's threads)."""
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT) + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    argv = list(argv)
    if workers == 1:
        env.update(ONE_THREAD)
    if kind == "sweep":
        env["NUMBA_NUM_THREADS"] = str(workers)
    else:
        argv[argv.index("--workers") + 1] = str(workers)
    return ["-m", "beveloid.cli", *argv], env


def timed(args: list, env: dict) -> tuple[float, float]:
    """(wall, CPU) seconds of ``python ARGS`` (its CPU: its own and its exited children's)."""
    t, before = time.perf_counter(), os.times()
    proc = subprocess.run([sys.executable, *args], capture_output=True, text=True, env=env, cwd=tempfile.gettempdir())
    wall, after = time.perf_counter() - t, os.times()
    if proc.returncode != 0:
        raise SystemExit(f"python {' '.join(args)}: exited {proc.returncode}:\n{proc.stderr[-3000:]}")
    return wall, (after.children_user - before.children_user) + (after.children_system - before.children_system)


#: the pieces of a process's start that ``starts`` times (fresh Pythons running these)
STARTS = {"bare Python": "pass", "numpy": "import numpy", "numpy, scipy.linalg": "import numpy, scipy.linalg",
          "numpy, numba": "import numpy, numba",
          "explore's worker start": "from beveloid import parallel; from beveloid.explore.run import warm_up;"
                                    " parallel.warm_up(warm_up)"}


def starts(workers: int, rounds: int) -> dict:
    """The ``starts`` measurement (module docstring): {piece: {"default"|"one_thread": [(wall, CPU), ...]},
    "at_once": {n: wall}}."""
    out = {}
    for name, code in STARTS.items():
        runs = {"default": [], "one_thread": []}
        for _ in range(rounds):
            for how in runs:
                env = dict(os.environ, PYTHONPATH=str(ROOT))
                if how == "one_thread":
                    env.update(ONE_THREAD)
                runs[how].append(timed(["-c", code], env))
        out[name] = runs
        print(f"{name}: {min(w for w, _ in runs['default']):.3f} s wall, {min(c for _, c in runs['default']):.3f} s"
              f" CPU; one BLAS thread {min(w for w, _ in runs['one_thread']):.3f} s wall,"
              f" {min(c for _, c in runs['one_thread']):.3f} s CPU", flush=True)
    env = dict(os.environ, PYTHONPATH=str(ROOT), **ONE_THREAD)
    out["at_once"] = {}
    for n in sorted({1, 4, workers}):
        t = time.perf_counter()
        procs = [subprocess.Popen([sys.executable, "-c", STARTS["explore's worker start"]], env=env,
                                  cwd=tempfile.gettempdir()) for _ in range(n)]
        if any(p.wait() for p in procs):
            raise SystemExit("a worker's start failed")
        out["at_once"][n] = time.perf_counter() - t
        print(f"{n} of explore's worker starts at once (one thread each): {out['at_once'][n]:.3f} s wall", flush=True)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("kinds", nargs="*", default=["explore", "sweep", "ltca", "optimize"])
    ap.add_argument("--workers", type=int, default=os.cpu_count(), help="W (default: this machine's cores)")
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--budget", type=int, default=128, help="optimize's candidates (default 128)")
    ap.add_argument("--tooth-model", choices=("fe", "plate"), default=None)
    ap.add_argument("--json", type=Path, default=None, help="also write the runs here")
    a = ap.parse_args()
    report = {"cpu_count": os.cpu_count(), "workers": a.workers, "kinds": {}}
    print(f"{os.cpu_count()} cores, W = {a.workers}, load average {load_average():.1f}", flush=True)
    if "starts" in a.kinds:
        a.kinds.remove("starts")
        report["starts"] = starts(a.workers, a.rounds)
    with tempfile.TemporaryDirectory(prefix="many_") as tmp_name:
        tmp = Path(tmp_name)
        cmds = commands(tmp, a.budget)
        for kind in a.kinds:
            argv = list(cmds[kind])
            if a.tooth_model and kind in ("ltca", "optimize"):
                if "--tooth-model" in argv:
                    argv[argv.index("--tooth-model") + 1] = a.tooth_model
                else:
                    argv += ["--tooth-model", a.tooth_model]
            timed(*with_workers(kind, small(kind, argv), 1))  # numba's cache, the FE data
            runs = {1: [], a.workers: []}
            for r in range(a.rounds):
                for w in (1, a.workers):
                    for path in tmp.glob("*/"):
                        subprocess.run(["rm", "-rf", str(path)], check=True)
                    wall, cpu = timed(*with_workers(kind, argv, w))
                    runs[w].append({"wall_s": wall, "cpu_s": cpu})
                    print(f"{kind} round {r + 1}, {w} worker(s): {wall:.2f} s wall, {cpu:.2f} s CPU"
                          f" (load {load_average():.1f})", flush=True)
            t1, tw = (min(x["wall_s"] for x in runs[w]) for w in (1, a.workers))
            print(f"{kind}: one worker {t1:.2f} s, {a.workers} workers {tw:.2f} s: speed-up {t1 / tw:.2f}x (least of"
                  f" {a.rounds}); the serial share that speed-up implies (Amdahl): "
                  f"{100 * (a.workers / (t1 / tw) - 1) / (a.workers - 1):.1f} %", flush=True)
            print(f"  command (one worker's form): beveloid {' '.join(Path(x).name if x.startswith(str(tmp)) else x for x in argv)}",
                  flush=True)
            report["kinds"][kind] = {"command": [Path(x).name if x.startswith(str(tmp)) else x for x in argv],
                                     "runs": {str(w): v for w, v in runs.items()}, "speed_up": t1 / tw}
    if a.json:
        a.json.write_text(json.dumps(report, indent=1))


if __name__ == "__main__":
    main()

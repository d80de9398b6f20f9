"""Where the first `beveloid paper` spends its CPU: each piece its worker processes run (the FE data of
each member, the compiles, the studies), and the rest (the main process: the solver core's compile,
Fig 22, the report; the workers' start-up).

    python benchmarks/paper_pieces.py                  # this checkout, a fresh cache folder
    python benchmarks/paper_pieces.py --positions 200  # `paper --positions` (default 200, its default)

`python -m beveloid.cli paper --out DIR` runs with BEVELOID_CACHE_DIR an empty folder (numba's compile
and the FE data as on a fresh install) and, first on PYTHONPATH, a folder whose sitecustomize.py wraps
`beveloid.studies.tasks._run_piece` in every process (the workers are spawned: each runs it) to say on
stderr, per piece, its CPU (user + system) and wall seconds.  Not a test; the machine's other work is
not controlled (the load average before the run is printed).
"""
from __future__ import annotations

import argparse
import os
import re
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
TAG = "paper_pieces:"

SITECUSTOMIZE = f'''
import os, time
try:
    from beveloid.studies import tasks as _tasks
except Exception:  # not this package's interpreter: nothing to wrap
    _tasks = None
if _tasks is not None:
    _run = _tasks._run_piece

    def _timed(fn, args):
        c0, s0, w0 = time.process_time(), os.times().system, time.perf_counter()
        try:
            return _run(fn, args)
        finally:
            name = f"{{fn.__module__.rsplit('.', 1)[-1]}}.{{fn.__qualname__}}{{args[:2]!r}}"
            _tasks.say(f"{TAG} {{name}} cpu {{time.process_time() - c0:.2f}} "
                       f"sys {{os.times().system - s0:.2f}} wall {{time.perf_counter() - w0:.2f}}")

    _tasks._run_piece = _timed
'''

LINE = re.compile(rf"^{TAG} (?P<name>.*) cpu (?P<cpu>\S+) sys (?P<sys>\S+) wall (?P<wall>\S+)$")


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--positions", type=int, default=200, help="`paper --positions` (default 200)")
    args = p.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="paper_pieces_") as tmp:
        tmp = Path(tmp)
        (tmp / "site").mkdir()
        (tmp / "site" / "sitecustomize.py").write_text(SITECUSTOMIZE)
        env = dict(os.environ, BEVELOID_CACHE_DIR=str(tmp / "cache"), BEVELOID_MODELS_DIR=str(tmp / "models"),
                   PYTHONPATH=os.pathsep.join([str(tmp / "site"), str(ROOT)]))
        env.pop("NUMBA_CACHE_DIR", None)
        load = os.getloadavg()[0]
        r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        t0 = time.perf_counter()
        proc = subprocess.run([sys.executable, "-m", "beveloid.cli", "paper", "--out", str(tmp / "out"),
                               "--positions", str(args.positions)], cwd=tmp, env=env, capture_output=True, text=True)
        wall = time.perf_counter() - t0
        r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode != 0:
        raise SystemExit(f"beveloid paper failed ({proc.returncode}):\n{proc.stderr[-2000:]}")
    pieces = [m.groupdict() for m in map(LINE.match, proc.stderr.splitlines()) if m]
    if not pieces:
        raise SystemExit("no piece timings on stderr (on one core `paper` runs its pieces in its own process)")
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    sys_s = r1.ru_stime - r0.ru_stime
    print(f"`beveloid paper --positions {args.positions}`, fresh cache: {wall:.1f} s wall, {cpu:.1f} s CPU "
          f"({sys_s:.1f} s system) in all processes; {os.cpu_count()} cores; load average before {load:.2f}")
    print(f"{'piece':<58} {'CPU s':>7} {'system':>7} {'wall s':>7}")
    total = 0.0
    for d in sorted(pieces, key=lambda d: -float(d["cpu"])):
        total += float(d["cpu"])
        print(f"{d['name'][:58]:<58} {float(d['cpu']):7.2f} {float(d['sys']):7.2f} {float(d['wall']):7.2f}")
    print(f"{'the pieces':<58} {total:7.2f}")
    print(f"{'the rest (main process: core compile, Fig 22, report; start-up)':<58} {cpu - total:7.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

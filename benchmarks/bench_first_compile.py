"""The first `beveloid tca` after an installation or a change of the models (`derive --model`): numba
compiles the solver core once, then caches it.  Measured as a user meets it: the command with an empty
cache folder (BEVELOID_CACHE_DIR, where numba's cache then goes), then the same command again (cached).

    python benchmarks/bench_first_compile.py            # a table
    python benchmarks/bench_first_compile.py --json     # the record docs/readme_numbers.py keeps
    python benchmarks/bench_first_compile.py --by-function   # where the first compile's CPU goes

``--by-function`` runs the same command once, with an empty cache folder, in a child that listens to
numba's compile events (``numba.core.event``, "numba:compile"): each compiled function's own CPU seconds
(its compile less the compiles of the callees it triggered), summed by where the function lives (each
generated surface model, the rest of generated/, the solver core, the rest of beveloid).

Per run: wall seconds, CPU seconds (user + system of the command and its processes, from the
children's rusage) and the load average before it started.  The machine's other work is not
controlled: the CPU seconds are the comparable figure, the wall time depends on the load.
"""
from __future__ import annotations

import argparse
import collections
import json
import os
import resource
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
ARGS = ["tca", "examples/case1.toml", "--positions", "3"]


def timed(argv, env) -> dict:
    load = os.getloadavg()[0]
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "beveloid.cli", *argv], cwd=ROOT, env=env, capture_output=True,
                          text=True)
    wall = time.perf_counter() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode != 0:
        raise SystemExit(f"beveloid {' '.join(argv)} failed ({proc.returncode}):\n{proc.stderr[-2000:]}")
    return {"wall_s": round(wall, 1), "cpu_s": round((r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime), 1),
            "load_before": round(load, 2), "announced": "compiling the contact solver" in proc.stderr}


def _where(module: str) -> str:
    """The group of a compiled function by its module: a surface model, generated/, the core, the rest."""
    name = module.split(".")[-1]
    if ".generated." in f".{module}." or module.startswith("generated"):
        if name.startswith("surface_") and name.endswith("_scalar"):
            return "generated: surface model " + name[len("surface_"):-len("_scalar")]
        return "generated: the other kernels"
    if ".solver." in module:
        return "the solver core (beveloid/solver)"
    return "the rest (" + module + ")"


def by_function(cli_args) -> dict:
    """Run ``beveloid *cli_args`` in this process, listening to numba's compile events: each compiled
    function's exclusive CPU seconds (a thread's nested compiles subtracted)."""
    from numba.core import event

    from beveloid.cli import main as cli_main

    own = collections.defaultdict(float)
    count = collections.Counter()
    local = threading.local()

    class Listener(event.Listener):
        def on_start(self, ev):
            stack = local.__dict__.setdefault("stack", [])
            fn = ev.data["dispatcher"].py_func
            stack.append([fn.__module__, fn.__name__.split("__")[0], time.thread_time(), 0.0])

        def on_end(self, ev):
            stack = local.stack
            module, name, t0, callees = stack.pop()
            spent = time.thread_time() - t0
            own[(module, name)] += spent - callees
            count[(module, name)] += 1
            if stack:
                stack[-1][3] += spent

    t0 = time.process_time()
    with event.install_listener("numba:compile", Listener()):
        rc = cli_main(list(cli_args))
    total = time.process_time() - t0
    groups = collections.defaultdict(float)
    for (module, _), seconds in own.items():
        groups[_where(module)] += seconds
    top = sorted(own.items(), key=lambda kv: -kv[1])[:15]
    return {"command": "beveloid " + " ".join(cli_args), "rc": rc, "process_cpu_s": round(total, 1),
            "compile_cpu_s": round(sum(own.values()), 1),
            "groups_cpu_s": {k: round(v, 1) for k, v in sorted(groups.items(), key=lambda kv: -kv[1])},
            "functions": [{"function": f"{m}.{n}", "cpu_s": round(v, 2), "compiles": count[(m, n)]}
                          for (m, n), v in top]}


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--json", action="store_true", help="print the record as JSON")
    p.add_argument("--by-function", action="store_true",
                   help="one first run, its compile CPU by compiled function and by where it lives")
    p.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    if args.child:  # the --by-function run itself, in a process of its own with an empty cache folder
        print(json.dumps(by_function(ARGS)))
        return 0
    if args.by_function:
        with tempfile.TemporaryDirectory(prefix="bench_compile_") as tmp:
            env = dict(os.environ, BEVELOID_CACHE_DIR=tmp)
            env.pop("NUMBA_CACHE_DIR", None)
            proc = subprocess.run([sys.executable, __file__, "--child"], cwd=ROOT, env=env, capture_output=True,
                                  text=True)
        if proc.returncode != 0:
            raise SystemExit(f"the --by-function child failed ({proc.returncode}):\n{proc.stderr[-2000:]}")
        record = json.loads(proc.stdout.strip().splitlines()[-1])
        if args.json:
            print(json.dumps(record))
            return 0
        print(f"`{record['command']}`, an empty cache folder: {record['process_cpu_s']} s of CPU, of which "
              f"{record['compile_cpu_s']} s compiling (numba's compile events, each function's own share)")
        for where, seconds in record["groups_cpu_s"].items():
            print(f"  {seconds:7.1f} s  {where}")
        print("the functions that took longest:")
        for row in record["functions"]:
            print(f"  {row['cpu_s']:7.2f} s  {row['function']}" + (f" ({row['compiles']} compiles)"
                                                                  if row["compiles"] > 1 else ""))
        return 0
    with tempfile.TemporaryDirectory(prefix="bench_compile_") as tmp:
        env = dict(os.environ, BEVELOID_CACHE_DIR=tmp)
        env.pop("NUMBA_CACHE_DIR", None)
        first, again = timed(ARGS, env), timed(ARGS, env)
    record = {"command": "beveloid " + " ".join(ARGS), "cores": os.cpu_count(), "first": first, "cached": again}
    if args.json:
        print(json.dumps(record))
    else:
        print(f"`{record['command']}` on {record['cores']} cores, an empty cache folder, then again:")
        for name in ("first", "cached"):
            r = record[name]
            print(f"  {name:<7} {r['wall_s']:7.1f} s wall  {r['cpu_s']:7.1f} s CPU  load before {r['load_before']:.2f}"
                  f"{'  (announced the compile)' if r['announced'] else ''}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

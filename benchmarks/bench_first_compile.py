"""The first `beveloid tca` after an installation or a change of the models (`derive --model`): numba
compiles the solver core once, then caches it.  Measured as a user meets it: the command with an empty
cache folder (BEVELOID_CACHE_DIR, where numba's cache then goes), then the same command again (cached).

    python benchmarks/bench_first_compile.py            # a table
    python benchmarks/bench_first_compile.py --json     # the record docs/readme_numbers.py keeps

Per run: wall seconds, CPU seconds (user + system of the command and its processes, from the
children's rusage) and the load average before it started.  The machine's other work is not
controlled: the CPU seconds are the comparable figure, the wall time depends on the load.
"""
from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
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


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--json", action="store_true", help="print the record as JSON")
    args = p.parse_args(argv)
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

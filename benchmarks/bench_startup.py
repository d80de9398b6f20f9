"""Start-up of each command: wall time of a whole `beveloid ...` process, warm caches.

    python benchmarks/bench_startup.py              # table: median and min over --repeat runs
    python benchmarks/bench_startup.py --json
    python benchmarks/bench_startup.py --imports    # also the modules each command imports

Not a test.  Each command runs as its own process (``python -m beveloid.cli``), so the time is what
a user waits: interpreter start, imports, numba's cache loading, the work.  One untimed run of each
command first fills numba's cache (a cold cache is a compile, not a start-up).  Commands: ``--help``,
``example case1``, ``design`` and ``tca --positions 3`` on case 1 (the smallest real TCA), and
``tca --help`` (the command's imports without its work).
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path


def commands(spec: str) -> dict[str, list[str]]:
    return {
        "--help": ["--help"],
        "example case1": ["example", "case1"],
        "tca --help": ["tca", "--help"],
        "design case1": ["design", spec],
        "tca case1 --positions 3": ["tca", spec, "--positions", "3"],
    }


def _run(args: list[str], cwd: str, env: dict) -> float:
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "beveloid.cli", *args], cwd=cwd, env=env,
                          stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    seconds = time.perf_counter() - t0
    if proc.returncode != 0:
        raise SystemExit(f"beveloid {' '.join(args)} failed ({proc.returncode}): {proc.stderr.strip()}")
    return seconds


def _imports(args: list[str], cwd: str, env: dict) -> tuple[int, list[str]]:
    """How many modules the command imports, and which of the heavy ones."""
    code = ("import sys, runpy; sys.argv = ['beveloid'] + sys.argv[1:]\n"
            "try:\n    runpy.run_module('beveloid.cli', run_name='__main__')\n"
            "except SystemExit:\n    pass\n"
            "heavy = ('numba', 'scipy', 'matplotlib', 'sympy', 'beveloid.tca', 'beveloid.solver', 'beveloid.design')\n"
            "print(len(sys.modules), ' '.join(sorted({m for m in sys.modules if m in heavy})), file=sys.stderr)\n")
    proc = subprocess.run([sys.executable, "-c", code, *args], cwd=cwd, env=env, stdout=subprocess.DEVNULL,
                          stderr=subprocess.PIPE, text=True)
    count, *heavy = proc.stderr.strip().splitlines()[-1].split()
    return int(count), heavy


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=7, help="timed runs per command (default 7)")
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--imports", action="store_true", help="count the modules each command imports")
    args = ap.parse_args()
    env = {**os.environ, "PYTHONDONTWRITEBYTECODE": "0"}
    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        spec = str(Path(tmp) / "case1.toml")
        with open(spec, "w") as f:
            subprocess.run([sys.executable, "-m", "beveloid.cli", "example", "case1"], stdout=f, check=True, env=env)
        for name, argv in commands(spec).items():
            _run(argv, tmp, env)  # warm: numba's cache, the OS's file cache, .pyc files
            times = [_run(argv, tmp, env) for _ in range(args.repeat)]
            out[name] = {"median_s": statistics.median(times), "min_s": min(times), "runs": len(times)}
            if args.imports:
                out[name]["modules"], out[name]["heavy_modules"] = _imports(argv, tmp, env)
    if args.json:
        print(json.dumps(out, indent=2))
        return
    print(f"{'command':<26} {'median (s)':>10} {'min (s)':>8}" + ("  modules  heavy" if args.imports else ""))
    for name, r in out.items():
        extra = f"  {r['modules']:>7}  {' '.join(r['heavy_modules'])}" if args.imports else ""
        print(f"beveloid {name:<17} {r['median_s']:>10.3f} {r['min_s']:>8.3f}{extra}")


if __name__ == "__main__":
    main()

"""Start-up of each command: wall time of a whole `beveloid ...` process, warm caches.

    python benchmarks/bench_startup.py              # table: median and min over --repeat runs
    python benchmarks/bench_startup.py --json
    python benchmarks/bench_startup.py --imports    # also the modules each command imports
    python benchmarks/bench_startup.py --compare OTHER_CHECKOUT   # before/after, alternating, one run
    python benchmarks/bench_startup.py --floor      # what numpy and numba cost before any beveloid code
    python benchmarks/bench_startup.py --only "tca case1"   # one command (repeatable)

Not a test.  Each command runs as its own process (``python -m beveloid.cli``), so the time is what
a user waits: interpreter start, imports, numba's cache loading, the work.  One untimed run of each
command first fills numba's cache (a cold cache is a compile, not a start-up).  Commands: ``--help``,
``example case1``, ``tca --help`` (the command's imports without its work), and on case 1
``design``, ``tca`` (its defaults: 200 positions, both flanks, contact ellipses), ``tca --positions 3``
(the smallest real TCA), ``ltca --torque-nm 200 --positions 3`` and ``sweep --samples 4
--positions 10``.

``--compare OTHER`` times each command also with the sources of another checkout (a folder holding
``beveloid/`` and ``generated/``, e.g. ``git archive main | tar -x -C /tmp/main``) first on
``PYTHONPATH``, the two alternating run by run, so a before/after ratio comes from one run on the
same load.  Python writes .pyc files here whatever the calling shell says (``PYTHONDONTWRITEBYTECODE``
is dropped: a user's install has them, and compiling ~70 modules from source costs ~0.1 s a run).
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
        "tca case1": ["tca", spec],
        "tca case1 --positions 3": ["tca", spec, "--positions", "3"],
        "ltca case1 (3 positions)": ["ltca", spec, "--torque-nm", "200", "--positions", "3"],
        "sweep case1 (4 x 10)": ["sweep", spec, "--samples", "4", "--positions", "10"],
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


#: ``python -c CODE``: the floor under a command that runs the compiled solver
FLOOR = {
    "python (nothing)": "pass",
    "import numpy": "import numpy",
    "import numba (+ scipy.linalg by numba's BLAS check)": "import numba, numba.np.arraymath",
    "+ numba's target refresh (first cache load)":
        "import numba; from numba.core.registry import cpu_target; cpu_target.target_context.refresh()",
    "+ gc.freeze() before the exit (as the CLI)":
        "import numba, gc; from numba.core.registry import cpu_target; cpu_target.target_context.refresh(); gc.freeze()",
}


def _floor(repeat: int, env: dict) -> None:
    print(f"{'python -c ...':<55} {'median (s)':>10} {'min (s)':>8}")
    for name, code in FLOOR.items():
        times = []
        for _ in range(repeat):
            t0 = time.perf_counter()
            subprocess.run([sys.executable, "-c", code], check=True, env=env)
            times.append(time.perf_counter() - t0)
        print(f"{name:<55} {statistics.median(times):>10.3f} {min(times):>8.3f}")


def _time(argv, cwd, envs, repeat):
    """{label: {median_s, min_s, runs}} with the runs of the environments interleaved."""
    for env in envs.values():
        _run(argv, cwd, env)  # warm: numba's cache, the OS's file cache, .pyc files
    times = {label: [] for label in envs}
    for _ in range(repeat):
        for label, env in envs.items():
            times[label].append(_run(argv, cwd, env))
    return {label: {"median_s": statistics.median(t), "min_s": min(t), "runs": len(t)} for label, t in times.items()}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=7, help="timed runs per command (default 7)")
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--imports", action="store_true", help="count the modules each command imports")
    ap.add_argument("--compare", metavar="OTHER", help="another checkout's folder: time it too, alternating")
    ap.add_argument("--floor", action="store_true", help="time only numpy's and numba's own start-up")
    ap.add_argument("--only", action="append", metavar="NAME",
                    help="time only this command (a name of the table, e.g. 'tca case1'); repeatable")
    args = ap.parse_args()
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    if args.floor:
        _floor(args.repeat, env)
        return
    envs = {"this": env}
    if args.compare:
        other = str(Path(args.compare).resolve())
        if not (Path(other) / "beveloid" / "__init__.py").is_file():
            raise SystemExit(f"--compare = {args.compare}: not a folder holding beveloid/__init__.py")
        envs = {"other": {**env, "PYTHONPATH": os.pathsep.join(filter(None, [other, env.get("PYTHONPATH")]))},
                "this": env}
    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        spec = str(Path(tmp) / "case1.toml")
        with open(spec, "w") as f:
            subprocess.run([sys.executable, "-m", "beveloid.cli", "example", "case1"], stdout=f, check=True, env=env)
        chosen = commands(spec)
        unknown = set(args.only or ()) - set(chosen)
        if unknown:
            raise SystemExit(f"--only: unknown command {sorted(unknown)}; choose from {sorted(chosen)}")
        for name, argv in chosen.items():
            if args.only and name not in args.only:
                continue
            out[name] = _time(argv, tmp, envs, args.repeat)
            if args.imports:
                for label, e in envs.items():
                    out[name][label]["modules"], out[name][label]["heavy_modules"] = _imports(argv, tmp, e)
    if args.json:
        print(json.dumps(out, indent=2))
        return
    labels = list(envs)
    head = "".join(f" {label + ' median (s)':>18} {'min (s)':>8}" for label in labels)
    print(f"{'command':<35}{head}" + ("  ratio" if len(labels) == 2 else "") + ("  modules  heavy" if args.imports else ""))
    for name, r in out.items():
        row = "".join(f" {r[label]['median_s']:>18.3f} {r[label]['min_s']:>8.3f}" for label in labels)
        if len(labels) == 2:
            row += f"  {r['this']['median_s'] / r['other']['median_s']:>5.2f}"
        if args.imports:
            row += "".join(f"  {r[label]['modules']:>7}  {' '.join(r[label]['heavy_modules'])}" for label in labels)
        print(f"beveloid {name:<26}{row}")


if __name__ == "__main__":
    main()

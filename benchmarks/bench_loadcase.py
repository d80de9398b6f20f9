"""Issue 56 (the load case apart from the options, ltca/ redrawn): the same numbers as an older checkout, and
no slower, in one run.

    git worktree add --detach /tmp/before 9a28992
    python benchmarks/bench_loadcase.py /tmp/before [--repeats 3]

Each checkout runs in its own processes (its own beveloid, on PYTHONPATH), through whichever API it has
(``ltca.LoadCase`` or the torque inside ``ltca.Options``), on the shipped cases:

* tca: case1 and case2, both flanks, 200 positions;
* ltca: case1 and case2 at 400 N m (right flank, 20 positions, the plate tooth, the default grid), and
  case1's FE tooth (every element size x 4, 5 positions);
* rating: case1 and case2 at 1000 N m (the plate tooth, 10 positions: the same request in both);
* sweep: case1's right flank, 4000 error sets x 20 positions, seed 0;
* explore: ``explore.rows.compute`` of bench_explore.py's 64-design grid, with the whole-tooth checks;
* optimize: ``beveloid optimize`` (case1, pinion lead crowning 0-40 um, 100 and 300 N m, 8 candidates,
  population 4, 5 positions on a 7x9 grid, the plate tooth, no constraint, one worker): candidates.csv
  (its seconds column left out) and pareto.csv.

Every array and number of each result is compared bit for bit (array_equal, NaN equal to NaN; a run's
own timings left out); a field one checkout has and the other lacks is listed, not compared.  Times: sweep, explore, ltca (the two
plate runs, after a warm-up in the same process) and optimize, old and new alternated ``--repeats`` times
in this one run (the machine is shared: a ratio of times measured side by side); the median of each.
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

import numpy as np

_WORKER = r'''
import csv, dataclasses, json, os, sys, tempfile, time
from collections.abc import Mapping
sys.path[:0] = [os.getcwd(), os.path.join(os.getcwd(), "benchmarks")]
import numpy as np

task, out_file = sys.argv[1], sys.argv[2]
SKIP = {"pair", "options", "spec", "geometry", "geom", "load", "seconds", "seconds_total"}  # inputs; timings


def collect(obj, name, out, depth=0):
    """Every number and array under ``obj`` by its path (dataclass fields, mappings, named tuples)."""
    if depth > 4 or obj is None:
        return
    if isinstance(obj, np.ndarray):
        if obj.dtype.kind in "fiub":
            out[name] = np.asarray(obj)
        elif obj.dtype == object and obj.size and all(isinstance(v, str) for v in obj.ravel()):
            out[name] = np.asarray(obj, dtype=str)
        return
    if isinstance(obj, (bool, np.bool_)):
        out[name] = np.asarray(obj)
        return
    if isinstance(obj, (int, float, np.number)):
        out[name] = np.asarray(obj, dtype=float)
        return
    if isinstance(obj, str):
        out[name] = np.asarray(str(obj))
        return
    if dataclasses.is_dataclass(obj):
        for f in dataclasses.fields(obj):
            if f.name not in SKIP and not f.name.startswith("_"):
                collect(getattr(obj, f.name), f"{name}.{f.name}", out, depth + 1)
        return
    if isinstance(obj, Mapping):
        for k, v in obj.items():
            collect(v, f"{name}[{str(k)}]", out, depth + 1)
        return
    if isinstance(obj, tuple) and hasattr(obj, "_fields"):
        for k in obj._fields:
            collect(getattr(obj, k), f"{name}.{k}", out, depth + 1)
        return
    if isinstance(obj, (tuple, list)):
        if obj and all(isinstance(v, str) for v in obj):
            out[name] = np.asarray([str(v) for v in obj])
            return
        try:
            a = np.asarray(obj)
        except ValueError:
            a = None
        if a is not None and a.dtype.kind in "fiub":
            out[name] = a
            return
        for i, v in enumerate(obj):
            collect(v, f"{name}[{i}]", out, depth + 1)


from beveloid import ltca, rating, sweep, tca
from beveloid.pair import Pair

NEW = hasattr(ltca, "LoadCase")  # the load case apart from the options (issue 56)


def loaded(pair, torque, **opts):
    if NEW:
        return ltca.analyze(pair, ltca.LoadCase(torque), ltca.Options(**opts))
    return ltca.analyze(pair, ltca.Options(torque_nm=torque, **opts))


def rated(pair, torque, **opts):
    if NEW:
        return rating.analyze(pair, ltca.LoadCase(torque), rating.Options(ltca.Options(**opts)))
    return rating.analyze(pair, rating.Options(torque_nm=torque, **opts))


arrays, seconds = {}, None
cases = {c: Pair.example(c) for c in ("case1", "case2")}
if task == "tca":
    for c, pair in cases.items():
        collect(tca.analyze(pair, tca.Options(positions=200)), c, arrays)
elif task == "ltca":
    plate = dict(flank="right", positions=20, tooth_model="plate")
    loaded(cases["case1"], 400.0, **plate)  # warm-up: numba's caches
    t = time.perf_counter()
    for c, pair in cases.items():
        collect(loaded(pair, 400.0, **plate), c, arrays)
    seconds = time.perf_counter() - t
    collect(loaded(cases["case1"], 400.0, positions=5, tooth_model="fe", fe_coarsen=4.0), "case1_fe", arrays)
elif task == "rating":
    for c, pair in cases.items():
        collect(rated(pair, 1000.0, positions=10, tooth_model="plate"), c, arrays)
elif task == "sweep":
    geom = cases["case1"].geometry
    options = sweep.Options(flank="right", samples=4000, positions=20, seed=0)
    sweep.analyze(geom, sweep.Options(flank="right", samples=8, positions=5, seed=0))  # warm-up
    t = time.perf_counter()
    collect(sweep.analyze(geom, options), "case1", arrays)
    seconds = time.perf_counter() - t
elif task == "explore":
    from bench_explore import _plan
    from beveloid.explore import rows
    from beveloid.sweep import DEFAULT_RANGES

    plan = _plan(64)
    rows.compute(plan, 0, 4, DEFAULT_RANGES)  # warm-up
    t = time.perf_counter()
    collect(rows.compute(plan, 0, plan.count, DEFAULT_RANGES), "grid64", arrays)
    seconds = time.perf_counter() - t
elif task == "optimize":
    from beveloid.cli import main

    folder = tempfile.mkdtemp(prefix="bench_loadcase_")
    spec = os.path.join(os.getcwd(), "examples", "case1.toml")
    argv = ["optimize", spec, "--vary", "pinion.lead_crowning_um=0:40", "--torque-nm", "100,300", "--budget", "8",
            "--population", "4", "--positions", "5", "--grid", "7x9", "--tooth-model", "plate", "--constraints",
            "none", "--workers", "1", "--out", os.path.join(folder, "run"), "--seed", "0"]
    t = time.perf_counter()
    rc = main(argv)
    seconds = time.perf_counter() - t
    assert rc == 0, rc
    for name in ("candidates", "pareto"):
        with open(os.path.join(folder, "run", f"{name}.csv")) as fh:
            for i, row in enumerate(csv.DictReader(fh)):
                for k, v in row.items():
                    if k != "seconds":
                        arrays[f"{name}[{i}].{k}"] = np.asarray(v)
np.savez(out_file, **arrays)
print(json.dumps({"seconds": seconds, "api": "LoadCase" if NEW else "Options(torque_nm)"}))
'''

TASKS = ("tca", "ltca", "rating", "sweep", "explore", "optimize")
TIMED = ("sweep", "explore", "ltca", "optimize")


def _run(where, task, out_file):
    env = dict(os.environ, PYTHONPATH=where, MPLBACKEND="Agg")
    p = subprocess.run([sys.executable, "-c", _WORKER, task, out_file], cwd=where, capture_output=True, text=True,
                       env=env)
    if p.returncode != 0:
        raise SystemExit(f"{task} in {where} failed:\n{p.stderr[-3000:]}")
    return json.loads(p.stdout.strip().splitlines()[-1])


def _compare(old_file, new_file):
    old, new = np.load(old_file), np.load(new_file)
    common = sorted(set(old.files) & set(new.files))
    differ = []
    for k in common:
        a, b = old[k], new[k]
        same = a.shape == b.shape and (np.array_equal(a, b, equal_nan=True) if a.dtype.kind in "fc"
                                       else np.array_equal(a, b))
        if not same:
            diff = ""
            if a.shape == b.shape and a.dtype.kind in "fiu" and b.dtype.kind in "fiu":
                with np.errstate(invalid="ignore"):
                    d = np.abs(a.astype(float) - b.astype(float))
                diff = f" (max |diff| {np.nanmax(d) if np.isfinite(d).any() else float('nan'):.3g})"
            differ.append(k + diff)
    return common, differ, sorted(set(old.files) - set(new.files)), sorted(set(new.files) - set(old.files))


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("before", metavar="CHECKOUT", help="the older checkout (a worktree of the commit to compare)")
    ap.add_argument("--repeats", type=int, default=3, help="timed runs of each checkout, alternated (default 3)")
    a = ap.parse_args(argv)
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    where = {"before": os.path.abspath(a.before), "after": here}
    times = {t: {"before": [], "after": []} for t in TIMED}
    with tempfile.TemporaryDirectory() as tmp:
        files = {}
        for task in TASKS:
            for r in range(a.repeats if task in TIMED else 1):
                order = ("before", "after") if r % 2 == 0 else ("after", "before")
                for side in order:
                    f = os.path.join(tmp, f"{task}_{side}_{r}.npz")
                    got = _run(where[side], task, f)
                    files.setdefault((task, side), f)
                    if task in TIMED:
                        times[task][side].append(got["seconds"])
        print("| result | values compared | differ | only before | only after |")
        print("|---|---|---|---|---|")
        for task in TASKS:
            common, differ, only_old, only_new = _compare(files[task, "before"], files[task, "after"])
            show = lambda names: ", ".join(names[:6]) + (f" (+{len(names) - 6})" if len(names) > 6 else "")  # noqa: E731
            print(f"| {task} | {len(common)} | {len(differ)}{': ' + show(differ) if differ else ''} | "
                  f"{len(only_old)}{': ' + show(only_old) if only_old else ''} | "
                  f"{len(only_new)}{': ' + show(only_new) if only_new else ''} |")
    print()
    print(f"| timed (median of {a.repeats}, s) | before | after | after / before |")
    print("|---|---|---|---|")
    for task in TIMED:
        b, n = statistics.median(times[task]["before"]), statistics.median(times[task]["after"])
        print(f"| {task} | {b:.2f} | {n:.2f} | {n / b:.3f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())

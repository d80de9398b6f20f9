"""The tolerance box under load, old tree against new in one run: time and numbers.

    python benchmarks/bench_tolerance_box.py --old DIR [--new DIR] [--rounds 2] [--samples 16]
        [--torques-nm 100,200,400] [--tooth-model fe] [--keep DIR] [--split]

    python benchmarks/bench_tolerance_box.py --old DIR --optimize BUDGET [--rounds 1] [--constraints none]

Not a test.  The command of issue 59 (docs/optimize.md's spec, case 1 tilted by vertical_deg = 0.05):

    beveloid ltca case1_tilted.toml --torque-nm 100,200,400 --samples 16 --json

run by each checkout (``--old``, ``--new``: folders holding a ``beveloid`` package; ``--new`` defaults to
this one) as a child process with that folder first on PYTHONPATH, one warm-up run each first (numba's
cache and the FE data of that tree's code made or read: "FE data cached"), then ``--rounds`` timed runs,
old and new alternating (the machine is shared: only ratios within one run mean anything).  Printed per
run: wall seconds and the child's CPU seconds (user + system); then the ratios new / old of the least of
each, and the numbers compared: every error set's quantities (``tolerance.sets``: TE peak-to-peak,
peak pressure, both root stresses) and every other number of the JSON (the torque map, each position's
arrays), as the largest relative difference |a - b| / max(|a|, |b|) over the leaves (the solver's
residuals, round-off, absolutely), and the count of leaves that differ in kind (a number against null,
a string, a list's length, a key only one tree writes).

``--bytecode``: both trees run with their sources' bytecode cached, as an installed package has it (``pip install``
compiles it): ``PYTHONDONTWRITEBYTECODE`` unset and ``PYTHONPYCACHEPREFIX`` a folder of the run's, which each tree's
warm-up run fills (neither tree's folder is written); without it, where ``PYTHONDONTWRITEBYTECODE`` is set (this
project's machines), every run compiles every module of the tree it imports from source (~0.3 s of either tree's CPU, issue 59).

``--split``: instead of the command's CPU, where it goes: each tree's child runs ``beveloid.cli.main`` with the
command's arguments twice in one process (:data:`SPLIT`); the CPU to the end of the first call (the process's start,
its imports, numba's cache loads, the FE data read, and the analyses: about the command's own CPU but its exit) and
the second call's (the analyses and their outputs alone: every module imported, every cache loaded); their
difference is the command's fixed part.  Printed: each part's least over the rounds for both trees, the ratios,
and what the new tree's analyses would have to cost for 0.4 x the old tree's first call at its fixed part.

``--optimize BUDGET``: docs/optimize.md section 6's command instead (``beveloid optimize case1_tilted.toml
--vary pinion.lead_crowning_um=0:40 --vary pinion.lead_slope_um=-30:30 --torque-nm 100,200,400 --weights
0.2,0.5,0.3 --samples 16 --tooth-model fe --budget BUDGET --workers 2 --json``), its JSON compared (the
front, the baseline, the picks); the warm-up runs with ``--budget 2``.  ``--constraints none`` adds that flag
(the front of the objectives alone: two trees whose rating verdicts differ then still share a front
where their loaded numbers agree).
"""
from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def spec_text(checkout: Path) -> str:
    out = subprocess.run([sys.executable, "-m", "beveloid.cli", "example", "case1"], capture_output=True, text=True,
                         check=True, env=_env(checkout), cwd=tempfile.gettempdir())
    return out.stdout.replace("vertical_deg = 0.0 ", "vertical_deg = 0.05", 1)


#: with --bytecode: the folder of both trees' cached bytecode (PYTHONPYCACHEPREFIX), None without
PYCACHE = None


def _env(checkout: Path) -> dict:
    env = dict(os.environ)
    if PYCACHE is not None:
        env.pop("PYTHONDONTWRITEBYTECODE", None)
        env["PYTHONPYCACHEPREFIX"] = str(PYCACHE)
    env["PYTHONPATH"] = str(checkout) + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    return env


def run(checkout: Path, argv: list, out: Path) -> tuple:
    """(wall s, child CPU s, JSON) of one ``beveloid`` command run by ``checkout``'s package."""
    before = os.times()
    t = time.perf_counter()
    with open(out, "w") as f:
        proc = subprocess.run([sys.executable, "-m", "beveloid.cli", *argv], stdout=f, stderr=subprocess.PIPE,
                              text=True, env=_env(checkout), cwd=tempfile.gettempdir())
    wall = time.perf_counter() - t
    after = os.times()
    if proc.returncode != 0:
        raise SystemExit(f"{checkout}: beveloid {' '.join(argv)} exited {proc.returncode}:\n{proc.stderr[-2000:]}")
    cpu = (after.children_user - before.children_user) + (after.children_system - before.children_system)
    return wall, cpu, json.loads(out.read_text())


#: the child of --split: argv[1:] the command's arguments; prints {"first": CPU s to the end of the first call
#: (time.process_time counts from the process's start), "again": the second call's CPU s}
SPLIT = """
import contextlib, io, json, sys, time
from beveloid.cli import main
argv = sys.argv[1:]
marks = []
for _ in range(2):
    with contextlib.redirect_stdout(io.StringIO()):
        main(argv)
    marks.append(time.process_time())
print(json.dumps({"first": marks[0], "again": marks[1] - marks[0]}))
"""


def split(checkout: Path, argv: list) -> dict:
    """:data:`SPLIT` run by ``checkout``'s package: {"first", "again"} CPU seconds."""
    proc = subprocess.run([sys.executable, "-c", SPLIT, *argv], capture_output=True, text=True, env=_env(checkout),
                          cwd=tempfile.gettempdir())
    if proc.returncode != 0:
        raise SystemExit(f"{checkout}: the split run exited {proc.returncode}:\n{proc.stderr[-2000:]}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def compare(a, b, path="", out=None) -> dict:
    """{"max_rel", "where", "kind", "numbers"} over the leaves of two JSON values."""
    out = out if out is not None else {"max_rel": 0.0, "where": None, "kind": [], "numbers": 0}
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            if k not in a or k not in b:
                out["kind"].append(f"{path}/{k}: only in {'old' if k in a else 'new'}")
            else:
                compare(a[k], b[k], f"{path}/{k}", out)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            out["kind"].append(f"{path}: lengths {len(a)} and {len(b)}")
        for i, (x, y) in enumerate(zip(a, b)):
            compare(x, y, f"{path}[{i}]", out)
    elif isinstance(a, (int, float)) and isinstance(b, (int, float)) and not isinstance(a, bool) \
            and not isinstance(b, bool):
        if "residual" in path:  # a solver's residual: round-off, compared absolutely
            out["residual"] = max(out.get("residual", 0.0), abs(a - b))
            return out
        out["numbers"] += 1
        scale = max(abs(a), abs(b))
        rel = abs(a - b) / scale if scale > 0 else 0.0
        if rel > out["max_rel"]:
            out["max_rel"], out["where"] = rel, path
    elif a != b:
        out["kind"].append(f"{path}: {str(a)[:60]!r} against {str(b)[:60]!r}")
    return out


def sets_only(doc) -> list:
    entries = doc["map"] if "map" in doc else [doc]
    return [e["tolerance"]["sets"] for e in entries]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--old", required=True, help="a folder holding the old tree's beveloid package")
    ap.add_argument("--new", default=str(ROOT), help="the new tree (default: this checkout)")
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--samples", type=int, default=16)
    ap.add_argument("--torques-nm", default="100,200,400")
    ap.add_argument("--tooth-model", choices=("fe", "plate"), default="fe")
    ap.add_argument("--keep", help="a folder for the spec and the JSON outputs (default: a temporary one)")
    ap.add_argument("--constraints", choices=("rating", "none"), default="rating",
                    help="with --optimize: its --constraints (default rating, section 6's command; none: the front of "
                         "the objectives alone, independent of the rating's verdict)")
    ap.add_argument("--optimize", type=int, metavar="BUDGET",
                    help="instead: docs/optimize.md section 6's `beveloid optimize` (2 workers, FE tooth, 3 torques, "
                         "16 sets) with --budget BUDGET, its --json compared (the run's seconds left out)")
    ap.add_argument("--split", action="store_true",
                    help="the command's CPU split into its fixed part and its analyses (two calls in one process)")
    ap.add_argument("--bytecode", action="store_true",
                    help="both trees with their bytecode cached (PYTHONPYCACHEPREFIX in the run's folder), as installed")
    a = ap.parse_args()
    if a.split and a.optimize:
        ap.error("--split times `beveloid ltca`'s box: not with --optimize")
    trees = {"old": Path(a.old).resolve(), "new": Path(a.new).resolve()}
    work = Path(a.keep or tempfile.mkdtemp(prefix="box_"))
    work.mkdir(parents=True, exist_ok=True)
    if a.bytecode:
        global PYCACHE
        PYCACHE = work / "pycache"
    spec = work / "case1_tilted.toml"
    spec.write_text(spec_text(trees["new"]))
    if a.optimize:
        argv = ["optimize", str(spec), "--vary", "pinion.lead_crowning_um=0:40", "--vary", "pinion.lead_slope_um=-30:30",
                "--torque-nm", a.torques_nm, "--weights", "0.2,0.5,0.3", "--samples", str(a.samples), "--tooth-model",
                a.tooth_model, "--budget", str(a.optimize), "--workers", "2", "--json"]
        if a.constraints != "rating":
            argv += ["--constraints", a.constraints]
    else:
        argv = ["ltca", str(spec), "--torque-nm", a.torques_nm, "--samples", str(a.samples), "--tooth-model",
                a.tooth_model, "--json"]
    out_dir = lambda tag: ["--out", str(work / tag)] if a.optimize else []  # noqa: E731
    print(f"beveloid {' '.join(argv[:1])} case1_tilted.toml {' '.join(argv[2:])}; load average "
          f"{os.getloadavg()[0]:.1f}{'; bytecode cached' if a.bytecode else ''}")
    docs, times = {}, {"old": [], "new": []}
    for name, tree in trees.items():  # warm-up: numba's cache and the FE data of each tree
        warm = [*argv[:argv.index("--budget") + 1], "2", *argv[argv.index("--budget") + 2:]] if a.optimize else argv
        w, c, docs[name] = run(tree, warm + out_dir(f"{name}_warm"), work / f"{name}_warm.json")
        print(f"  warm-up {name} ({tree}): {w:.2f} s wall, {c:.2f} s CPU")
    if a.split:
        return split_rounds(trees, argv, a.rounds)
    for r in range(a.rounds):
        for name in (("old", "new") if r % 2 == 0 else ("new", "old")):
            w, c, docs[name] = run(trees[name], argv + out_dir(f"{name}_{r}"), work / f"{name}_{r}.json")
            times[name].append((w, c))
            print(f"  round {r + 1} {name}: {w:.2f} s wall, {c:.2f} s CPU (load {os.getloadavg()[0]:.1f})")
    wo, co = min(t[0] for t in times["old"]), min(t[1] for t in times["old"])
    wn, cn = min(t[0] for t in times["new"]), min(t[1] for t in times["new"])
    print(f"least of {a.rounds}: old {wo:.2f} s wall, {co:.2f} s CPU; new {wn:.2f} s wall, {cn:.2f} s CPU; "
          f"new / old: wall {wn / wo:.3f}, CPU {cn / co:.3f}")
    if a.optimize:
        for d in docs.values():
            d.pop("seconds", None)
        w = compare(docs["old"], docs["new"])
        print(f"--json: {w['numbers']} numbers, largest relative difference {w['max_rel']:.2e} ({w['where']}); "
              f"{len(w['kind'])} differ in kind")
        for line in w["kind"][:10]:
            print(f"    {line}")
        return
    s = compare(sets_only(docs["old"]), sets_only(docs["new"]))
    print(f"error sets: {s['numbers']} numbers, largest relative difference {s['max_rel']:.2e} "
          f"({s['where']}); {len(s['kind'])} differ in kind")
    w = compare(docs["old"], docs["new"])
    print(f"whole JSON: {w['numbers']} numbers, largest relative difference {w['max_rel']:.2e} "
          f"({w['where']}); the solver's residuals within {w.get('residual', 0.0):.1e} of each other; "
          f"{len(w['kind'])} differ in kind")
    for line in w["kind"][:10]:
        print(f"    {line}")
    ok = math.isfinite(s["max_rel"]) and s["max_rel"] <= 1e-6 and not s["kind"]
    print(f"every set's numbers within 1e-6 relative: {'yes' if ok else 'no'}")


def split_rounds(trees, argv, rounds):
    """--split: both trees' :func:`split` alternating for ``rounds``; the least of each part printed."""
    parts = {"old": [], "new": []}
    for r in range(rounds):
        for name in (("old", "new") if r % 2 == 0 else ("new", "old")):
            t = split(trees[name], argv)
            parts[name].append(t)
            print(f"  round {r + 1} {name}: first call {t['first']:.2f} s CPU (fixed part {t['first'] - t['again']:.2f}, "
                  f"analyses {t['again']:.2f}) (load {os.getloadavg()[0]:.1f})")
    least = {n: {"first": min(t["first"] for t in ts), "again": min(t["again"] for t in ts),
                 "fixed": min(t["first"] - t["again"] for t in ts)} for n, ts in parts.items()}
    o, n = least["old"], least["new"]
    print(f"least of {rounds} (CPU s): first call old {o['first']:.2f}, new {n['first']:.2f} ({n['first'] / o['first']:.3f}); "
          f"fixed part old {o['fixed']:.2f}, new {n['fixed']:.2f} ({n['fixed'] / o['fixed']:.3f}); analyses old "
          f"{o['again']:.2f}, new {n['again']:.2f} ({n['again'] / o['again']:.3f})")
    print(f"0.4 x old's first call = {0.4 * o['first']:.2f} s: at new's fixed part the analyses would need "
          f"{0.4 * o['first'] - n['fixed']:.2f} s ({(0.4 * o['first'] - n['fixed']) / n['again']:.2f} x today's)")


if __name__ == "__main__":
    main()

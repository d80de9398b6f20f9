"""The README's first command, `beveloid paper --out DIR`, the first time: two versions of the code in
one run, alternating, each with a fresh cache folder (BEVELOID_CACHE_DIR pointing at an empty folder:
the FE teeth's data and numba's compiled solver are computed as on a fresh install).

    python benchmarks/bench_paper_first.py --old 691f171            # against that commit
    python benchmarks/bench_paper_first.py --old 691f171 --new HEAD --rounds 2 --positions 200

Each version is a `git archive` of its commit in a temporary folder, run as
`python -m beveloid.cli paper --out DIR` with that folder first on PYTHONPATH (the installed
package's dependencies, the checkout's code); ``--new`` defaults to the working tree itself.  Per run:
wall seconds, CPU seconds of the command and all its processes (user + system, from the children's
rusage), the load average of the machine before it started; then old / new per round and over all
rounds.  The machine's other work is not controlled: compare the ratios of one run, not times across runs.
Then how the outputs of round 1 differ (:func:`compare_outputs`): report.md's lines, PNGs pixel by pixel,
CSV cells (the same results, or which changed, between the two versions).
"""
from __future__ import annotations

import argparse
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def checkout(rev: str, where: Path) -> Path:
    """The tree of ``rev`` (git archive) in ``where``; "." is the working tree itself."""
    if rev == ".":
        return ROOT
    where.mkdir(parents=True)
    archive = subprocess.run(["git", "-C", str(ROOT), "archive", rev], check=True, capture_output=True).stdout
    subprocess.run(["tar", "-x", "-C", str(where)], input=archive, check=True)
    return where


def run_paper(code: Path, work: Path, positions: int) -> dict:
    """One first `beveloid paper` of the code in ``code``: wall and CPU seconds, load average before."""
    cache, out = work / "cache", work / "paper_out"
    cache.mkdir(parents=True)
    env = dict(os.environ, BEVELOID_CACHE_DIR=str(cache), PYTHONPATH=str(code),
               BEVELOID_MODELS_DIR=str(work / "models"))
    env.pop("NUMBA_CACHE_DIR", None)
    load = os.getloadavg()[0]
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "beveloid.cli", "paper", "--out", str(out), "--positions",
                           str(positions)], cwd=work, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode != 0:
        raise SystemExit(f"{code}: beveloid paper failed ({proc.returncode}):\n{proc.stderr[-2000:]}")
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    fe = sorted(p.name for p in (cache / "fe").glob("*.npz")) if (cache / "fe").is_dir() else []
    return {"wall_s": wall, "cpu_s": cpu, "load_before": load, "fe_entries": len(fe)}


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--old", required=True, help="the commit to compare against (e.g. the start of a change)")
    p.add_argument("--new", default=".", help="the commit of the new code (default: this working tree)")
    p.add_argument("--rounds", type=int, default=1, help="rounds of (old, new), the order alternating (default 1)")
    p.add_argument("--positions", type=int, default=200, help="`paper --positions` (default 200, its default)")
    args = p.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="bench_paper_") as tmp:
        tmp = Path(tmp)
        codes = {"old": checkout(args.old, tmp / "old"), "new": checkout(args.new, tmp / "new")}
        print(f"old = {args.old}, new = {args.new}; `beveloid paper --positions {args.positions}` with a fresh "
              f"BEVELOID_CACHE_DIR; {os.cpu_count()} cores; Python {sys.version.split()[0]}", flush=True)
        print(f"{'round':>5}  {'code':>4}  {'wall s':>8}  {'CPU s':>8}  {'load before':>11}  FE entries", flush=True)
        rows = []
        for k in range(args.rounds):
            order = ("old", "new") if k % 2 == 0 else ("new", "old")
            got = {}
            for which in order:
                work = tmp / f"run{k}_{which}"
                got[which] = run_paper(codes[which], work, args.positions)
                if k == 0:  # the first round's folders, compared at the end
                    shutil.move(work / "paper_out", tmp / f"out_{which}")
                shutil.rmtree(work, ignore_errors=True)
                g = got[which]
                print(f"{k + 1:>5}  {which:>4}  {g['wall_s']:8.1f}  {g['cpu_s']:8.1f}  {g['load_before']:11.2f}  "
                      f"{g['fe_entries']}", flush=True)
            rows.append(got)
            print(f"       round {k + 1}: old / new wall {got['old']['wall_s'] / got['new']['wall_s']:.2f}, "
                  f"CPU {got['old']['cpu_s'] / got['new']['cpu_s']:.2f}", flush=True)
        wall = sum(r["old"]["wall_s"] for r in rows) / sum(r["new"]["wall_s"] for r in rows)
        cpu = sum(r["old"]["cpu_s"] for r in rows) / sum(r["new"]["cpu_s"] for r in rows)
        print(f"all rounds: old / new wall {wall:.2f}, CPU {cpu:.2f}; load average now {os.getloadavg()[0]:.2f}")
        print("the outputs of round 1, old against new:")
        for line in compare_outputs(tmp / "out_old", tmp / "out_new"):
            print(f"  {line}")
    return 0


#: report.md's lines that hold a run's own time (they differ between any two runs)
TIMING = ("Computed in", "computed in")


def compare_outputs(old: Path, new: Path) -> list:
    """Lines saying how two `paper` folders differ: files in one only, report.md's lines (those that
    hold a run's time apart), PNGs pixel by pixel, CSV and text files cell by cell (the largest relative
    difference of the numbers)."""
    import csv

    import numpy as np
    from PIL import Image

    a, b = {p.name for p in old.iterdir()}, {p.name for p in new.iterdir()}
    out = [f"only in {which}: {', '.join(sorted(names))}" for which, names in (("old", a - b), ("new", b - a)) if names]
    ra, rb = (p.joinpath("report.md").read_text().splitlines() for p in (old, new))
    lines = [(x, y) for x, y in zip(ra, rb) if x != y]
    timing = sum(any(t in x for t in TIMING) and any(t in y for t in TIMING) for x, y in lines)
    out.append(f"report.md: {len(ra)} / {len(rb)} lines, {len(lines)} differ, {timing} of them the run's time")
    png = sorted(n for n in a & b if n.endswith(".png"))
    changed = [n for n in png if not np.array_equal(np.asarray(Image.open(old / n)), np.asarray(Image.open(new / n)))]
    out.append(f"PNG: {len(png) - len(changed)} of {len(png)} pixel-identical" + (f"; differ: {', '.join(changed)}"
                                                                                     if changed else ""))
    for n in sorted(n for n in a & b if n.endswith((".csv", ".txt"))):
        if (old / n).read_bytes() == (new / n).read_bytes():
            continue
        cells, worst = 0, 0.0
        with open(old / n, newline="") as f1, open(new / n, newline="") as f2:
            for r1, r2 in zip(csv.reader(f1), csv.reader(f2)):
                for u, v in zip(r1, r2):
                    if u == v:
                        continue
                    cells += 1
                    try:
                        x, y = float(u), float(v)
                        worst = max(worst, abs(x - y) / max(abs(x), abs(y), 1e-300))
                    except ValueError:
                        worst = float("inf")
        out.append(f"{n}: {cells} cells differ, the largest relative difference {worst:.1e}")
    return out


if __name__ == "__main__":
    raise SystemExit(main())

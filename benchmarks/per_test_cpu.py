"""Where the test suite's CPU goes: each test's own CPU time, per process, and what a fresh install adds.

A pytest plugin and its report.  As a plugin it records, in every test process (each xdist worker), the
process's CPU time (user + system: ``time.process_time``), its wall time and the CPU of the processes the test
started and waited for (the CLI tests' ``python -m beveloid.cli``, the local workers of ``--workers 2``:
``os.times``' children) over each test's setup, call and teardown, and writes them as ``<worker>.json`` to the
folder named by ``$PER_TEST_CPU_DIR``.  pytest's collection is not in it.

    PER_TEST_CPU_DIR=DIR PYTHONPATH=benchmarks pytest -p per_test_cpu -p no:cacheprovider
    python benchmarks/per_test_cpu.py DIR [WARM_DIR] [--top N]

The report prints the CPU in tests per worker, the most expensive tests and files, the tests whose started
processes used the most CPU (a worker process that compiled the solver again shows there: docs/performance.md,
"Test suite"); with ``WARM_DIR`` (the same
suite run again on the same caches) the tests whose CPU the first run exceeded most: numba's compilation
and whatever else a fresh install computes once (docs/performance.md, "Test suite").  The numbers are CPU
seconds, which the machine's other work inflates less than wall seconds, but does inflate (shared caches,
hyperthreads): compare runs made side by side.
"""
from __future__ import annotations

import argparse
import collections
import json
import os
import time
from pathlib import Path

import pytest

ENV = "PER_TEST_CPU_DIR"
_rows: dict = {}


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item, nextitem):
    cpu, wall, children = time.process_time(), time.perf_counter(), _children_cpu()
    yield
    _rows[item.nodeid] = (time.process_time() - cpu, time.perf_counter() - wall, _children_cpu() - children)


def _children_cpu() -> float:
    """User + system CPU of this process's children that have ended and been waited for."""
    t = os.times()
    return t.children_user + t.children_system


def pytest_sessionfinish(session):
    folder = os.environ.get(ENV)
    if folder and _rows:
        worker = os.environ.get("PYTEST_XDIST_WORKER", "main")
        Path(folder).mkdir(parents=True, exist_ok=True)
        Path(folder, f"{worker}.json").write_text(json.dumps(_rows))


def load(folder) -> dict:
    """{node id: (cpu s, wall s, worker, started processes' cpu s)} of a run's folder (0 for the last where a run
    recorded none)."""
    rows = {}
    for path in sorted(Path(folder).glob("*.json")):
        for node, (cpu, wall, *children) in json.loads(path.read_text()).items():
            rows[node] = (cpu, wall, path.stem, children[0] if children else 0.0)
    if not rows:
        raise SystemExit(f"{folder}: no <worker>.json files (run pytest with -p per_test_cpu and ${ENV} set)")
    return rows


def _short(node: str, width: int = 160) -> str:
    """A node id cut to ``width`` characters (a parametrised id can be thousands long)."""
    return node if len(node) <= width else node[:width - 3] + "..."


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("run", help="the folder of a run's <worker>.json files")
    ap.add_argument("warm", nargs="?", help="the folder of the same suite run again on the same caches")
    ap.add_argument("--top", type=int, default=15, help="how many tests and files to list (default 15)")
    args = ap.parse_args(argv)
    rows = load(args.run)
    by_worker = collections.Counter()
    by_file = collections.Counter()
    for node, (cpu, _, worker, _) in rows.items():
        by_worker[worker] += cpu
        by_file[node.split("::")[0]] += cpu
    total = sum(by_worker.values())
    print(f"{len(rows)} tests, {total:.1f} s of CPU in tests: "
          + ", ".join(f"{w} {s:.1f} s" for w, s in sorted(by_worker.items())))
    print(f"\nthe {args.top} most expensive tests (CPU s, wall s, worker):")
    for node, (cpu, wall, worker, _) in sorted(rows.items(), key=lambda kv: -kv[1][0])[:args.top]:
        print(f"  {cpu:7.1f} {wall:7.1f}  {worker}  {_short(node)}")
    started = sorted(((v[3], v[1], v[2], node) for node, v in rows.items() if v[3] > 0), reverse=True)
    print(f"\nthe processes the tests started: {sum(c for c, *_ in started):.1f} s of CPU in all; the {args.top} "
          "most (CPU s, the test's wall s, worker):")
    for children, wall, worker, node in started[:args.top]:
        print(f"  {children:7.1f} {wall:7.1f}  {worker}  {_short(node)}")
    print(f"\nthe {args.top} most expensive files (CPU s, share of all):")
    for name, cpu in by_file.most_common(args.top):
        print(f"  {cpu:7.1f} {100 * cpu / total:5.1f} %  {name}")
    if args.warm:
        warm = load(args.warm)
        more = {node: cpu - warm[node][0] for node, (cpu, *_) in rows.items() if node in warm}
        warm_total = sum(cpu for cpu, *_ in warm.values())
        print(f"\nagain on the same caches: {warm_total:.1f} s of CPU in tests; the first run's excess over it "
              f"{sum(v for v in more.values() if v > 0):.1f} s, most in:")
        for node, extra in sorted(more.items(), key=lambda kv: -kv[1])[:args.top]:
            print(f"  {extra:7.1f} ({rows[node][0]:.1f} -> {warm[node][0]:.1f})  {_short(node)}")


if __name__ == "__main__":
    main()

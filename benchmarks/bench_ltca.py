"""LTCA benchmark: the cost per mesh position of ``ltca.analyze`` at its defaults (3 tooth pairs).

    python benchmarks/bench_ltca.py [--torque-nm 200] [--case case1 | --spec FILE] [--flank right] [--positions 20] [--repeats 3] [--json] [--cpu-time]

Not a test.  One core: BLAS threads are set to 1 before numpy is imported.  Uses only the keyword
form ``ltca.analyze(geom, torque, flank, positions=N)`` that every version since issue 13 takes,
so the same script times an older checkout (``PYTHONPATH=old_tree python benchmarks/bench_ltca.py``)
in the same run.  Timed: median of --repeats after one warm-up run (which also loads numba's cache).
"""
from __future__ import annotations

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_v] = "1"

import argparse  # noqa: E402
import json  # noqa: E402
import statistics  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from beveloid import ltca  # noqa: E402
from beveloid.pair import Pair  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--torque-nm", type=float, default=200.0)
    ap.add_argument("--case", default="case1")
    ap.add_argument("--spec", default=None, help="a TOML spec instead of --case")
    ap.add_argument("--flank", default="right")
    ap.add_argument("--positions", type=int, default=20)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--cpu-time", action="store_true", help="time with this process's CPU time instead of wall time")
    a = ap.parse_args()
    clock = time.process_time if a.cpu_time else time.perf_counter
    g = Pair.from_spec(a.spec).geometry if a.spec else Pair.example(a.case).geometry
    if a.spec:
        a.case = a.spec
    run = lambda: ltca.analyze(g, a.torque_nm, a.flank, positions=a.positions)  # noqa: E731
    r = run()
    times = []
    for _ in range(a.repeats):
        t = clock()
        run()
        times.append(clock() - t)
    out = {"module": ltca.__file__, "case": a.case, "flank": a.flank, "torque_nm": a.torque_nm,
           "positions": a.positions, "cells_per_pair": r.grid.across_cells * r.grid.along_cells,
           "analyze_s": statistics.median(times), "per_position_ms": statistics.median(times) / a.positions * 1e3,
           "all_converged": bool(np.all(r.converged))}
    if a.json:
        print(json.dumps(out))
    else:
        print(f"LTCA {a.case} {a.flank}, {a.torque_nm:g} N m, {a.positions} positions, {out['cells_per_pair']} cells per"
              f" pair ({out['module']}): analyze {out['analyze_s']:.2f} s, {out['per_position_ms']:.1f} ms per "
              f"position, converged {out['all_converged']}")


if __name__ == "__main__":
    main()

"""The loaded contact pattern's cost: ``ltca.results.pattern.flank_pattern`` of both members (the envelope of
the pressure over the mesh cycle that ``ltca --plot`` and ``paper`` draw).

    python benchmarks/bench_pattern.py [--case case1] [--torque-nm 300] [--positions 20] [--repeats 3]
    PYTHONPATH=OTHER_CHECKOUT python benchmarks/bench_pattern.py ...   # the same with another tree

Not a test.  One LTCA (plate tooth) is solved first, untimed; then the two patterns are computed
--repeats times and the smallest CPU time is printed, with a digest of the two pressure envelopes
(equal digests: bit-identical patterns).
"""
from __future__ import annotations

import argparse
import hashlib
import time

from beveloid import ltca
from beveloid.ltca.results import pattern
from beveloid.pair import Pair


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--case", default="case1")
    ap.add_argument("--torque-nm", type=float, default=300.0)
    ap.add_argument("--positions", type=int, default=20)
    ap.add_argument("--repeats", type=int, default=3)
    a = ap.parse_args()
    pair = Pair.example(a.case)
    result = ltca.analyze(pair, ltca.LoadCase(a.torque_nm), ltca.Options(positions=a.positions, tooth_model="plate"))
    best, digest = float("inf"), None
    for _ in range(a.repeats):
        t0 = time.process_time()
        out = [pattern.flank_pattern(result, pair.geometry, m) for m in ("pinion", "gear")]
        best = min(best, time.process_time() - t0)
        digest = hashlib.sha256(b"".join(p.max_pressure_mpa.tobytes() for p in out)).hexdigest()[:16]
    print(f"flank_pattern, both members, {a.case}, {a.positions} positions: {best:.3f} s CPU (best of {a.repeats});"
          f" envelope digest {digest}; {pattern.__file__}")


if __name__ == "__main__":
    main()

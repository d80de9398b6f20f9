"""Is the FE tooth's root stress, the one that decides the rating's local S_F, converged?  (issue 57.5)

For each design and member: the largest root stress over the mesh cycle of the LTCA at the rating's
torque (K_A = K_v = 1 here) and default positions, with the FE tooth at --fe-coarsen 2 (every element
twice as large), at its default (refinement 1) and at --fe-refinement 2 (every element half as large),
and the default's distance from the refined value and from the Richardson extrapolation of the three
(order from the three levels, h = 2, 1, 1/2).  Prints a markdown table.

    python benchmarks/rating_root_convergence.py [--designs case1,case2,A,B,C] [--torque-scale 1]

The FE data of each level is built once per design and cached (refinement 2: minutes a member).
"""
from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from rating_invariance import DESIGNS, _torques  # noqa: E402

LEVELS = (("coarsen 2", 1, 2.0), ("default", 1, 1.0), ("refinement 2", 2, 1.0))
SHORT = {"A": 0, "B": 1, "C": 2}


def _pair(name):
    from beveloid.pair import Pair
    from beveloid.spec import spec_from_toml_bytes

    if name in ("case1", "case2"):
        return Pair.example(name)
    return Pair.from_spec(spec_from_toml_bytes(list(DESIGNS.values())[SHORT[name]].encode()))


def richardson(coarse, mid, fine):
    """(extrapolated value, order) of three values at h, h/2, h/4; None where they do not converge monotonically."""
    d1, d2 = mid - coarse, fine - mid
    if d1 == 0 or d2 == 0 or d1 * d2 < 0 or abs(d2) >= abs(d1):
        return None, None
    p = math.log(abs(d1 / d2), 2)
    return fine + d2 / (2 ** p - 1), p


def main(argv=None) -> int:
    from beveloid import ltca
    from beveloid.rating.analysis import POSITIONS

    a = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    a.add_argument("--designs", default="case1,case2,A,B,C")
    args = a.parse_args(argv)
    print("| design | T (N m) | member | root stress max (MPa): coarsen 2 / default / refinement 2 | default / "
          "refinement 2 − 1 | Richardson (order) | default / Richardson − 1 |")
    print("|---|---|---|---|---|---|---|")
    for name in args.designs.split(","):
        pair = _pair(name)
        torque = 1500.0 if name in ("case1", "case2") else _torques(pair)[1]
        values = {}
        for label, refinement, coarsen in LEVELS:
            t0 = time.perf_counter()
            r = ltca.analyze(pair, ltca.Options(torque_nm=torque, positions=POSITIONS, tooth_model="fe",
                                                fe_refinement=refinement, fe_coarsen=coarsen))
            values[label] = r.root_stress_max_mpa()
            print(f"  {name} {label}: {time.perf_counter() - t0:.0f} s", file=sys.stderr, flush=True)
        for m in ("pinion", "gear"):
            c, d, f = (values[label][m] for label, _, _ in LEVELS)
            ext, p = richardson(c, d, f)
            rich = "not monotonic" if ext is None else f"{ext:.1f} ({p:.2f})"
            off = "" if ext is None else f"{d / ext - 1:+.1%}"
            print(f"| {name} | {torque:g} | {m} | {c:.1f} / {d:.1f} / {f:.1f} | {d / f - 1:+.1%} | {rich} | {off} |",
                  flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

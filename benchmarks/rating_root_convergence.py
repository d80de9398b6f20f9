"""Is the FE tooth's root stress, the one that decides the rating's local S_F, converged?  (issue 57.5)

For each design and member: the largest root stress over the mesh cycle of the LTCA at the rating's
torque (K_A = K_v = 1 here) and default positions, with the FE tooth at --fe-coarsen 2 (every element
twice as large), at its default (refinement 1) and at --fe-refinement 2 (every element half as large),
and the default's distance from the refined value and from the Richardson extrapolation of the three
(order from the three levels, h = 2, 1, 1/2).  Prints a markdown table, and a second one: where the
default reads its maximum (face z from the toe and the heel, height above the root cone), the fillet's
smallest radius against its element size, and the rating's own estimate (beveloid/rating/root_convergence.py:
the default's loads read with the coarsened tooth, 3 |default / coarse - 1|) beside the default's
distance from refinement 2.

    python benchmarks/rating_root_convergence.py [--designs case1,case2,A,B,C] [--levels 0,1,2]

``--levels 0,1``: coarsen 2 and the default only (refinement 2 takes up to 17 GB and minutes a member).
The FE data of each level is built once per design and cached.
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
    from beveloid.rating.root_convergence import root_stress_convergence

    a = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    a.add_argument("--designs", default="case1,case2,A,B,C")
    a.add_argument("--levels", default="0,1,2", help="of coarsen 2, default, refinement 2 (0-based)")
    args = a.parse_args(argv)
    levels = [LEVELS[int(i)] for i in args.levels.split(",")]
    where_rows = []
    print("| design | T (N m) | member | root stress max (MPa): coarsen 2 / default / refinement 2 | default / "
          "refinement 2 − 1 | Richardson (order) | default / Richardson − 1 |")
    print("|---|---|---|---|---|---|---|")
    for name in args.designs.split(","):
        pair = _pair(name)
        torque = 1500.0 if name in ("case1", "case2") else _torques(pair)[1]
        values = {label: {"pinion": math.nan, "gear": math.nan} for label, _, _ in LEVELS}
        for label, refinement, coarsen in levels:
            t0 = time.perf_counter()
            r = ltca.analyze(pair, ltca.LoadCase(torque), ltca.Options(positions=POSITIONS, tooth_model="fe",
                                                                       fe_refinement=refinement, fe_coarsen=coarsen))
            values[label] = r.root_stress_max_mpa()
            print(f"  {name} {label}: {time.perf_counter() - t0:.0f} s", file=sys.stderr, flush=True)
            if label == "default":
                where_rows += _where(name, torque, pair, r, root_stress_convergence(pair, r, ltca.Material.from_spec(pair.spec)))
        for m in ("pinion", "gear"):
            c, d, f = (values[label][m] for label, _, _ in LEVELS)
            ext, p = richardson(c, d, f) if math.isfinite(f) else (None, None)
            rich = "not monotonic" if ext is None else f"{ext:.1f} ({p:.2f})"
            off = "" if ext is None else f"{d / ext - 1:+.1%}"
            print(f"| {name} | {torque:g} | {m} | {c:.1f} / {d:.1f} / {f:.1f} | {d / f - 1:+.1%} | {rich} | {off} |",
                  flush=True)
    print("\n| design | member | max at face z from toe / heel (mm), height above root (mm) | fillet radius min / "
          "fillet element (mm) | coarse reading of the default's loads / default (MPa) | rating's estimate "
          "3 x change |")
    print("|---|---|---|---|---|---|")
    for row in where_rows:
        print(row)
    return 0


def _where(name, torque, pair, result, estimate) -> list:
    """The second table's rows of one design (module docstring)."""
    rows = []
    at = result.root_stress_location()
    for m in ("pinion", "gear"):
        e, w = estimate[m], at[m]
        toe, heel = sorted(pair.geometry.member(m).face_limits)
        rows.append(f"| {name} | {m} | {w['z_mm'] - toe:.2f} / {heel - w['z_mm']:.2f}, {w['height_mm']:.3f} | "
                    f"{e['fillet_radius_mm']:.3f} / {e['fillet_element_mm']:.3f} | {e['coarse_mpa']:.1f} / "
                    f"{e['default_mpa']:.1f} | {e['error_estimate']:.1%} |")
    return rows


if __name__ == "__main__":
    raise SystemExit(main())

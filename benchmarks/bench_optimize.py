"""What `beveloid optimize` costs in the issue's target configuration.

    python benchmarks/bench_optimize.py [--tooth-model fe|plate] [--sets 1] [--positions 20] [--fe-coarsen 1]

The target: case 1 (here tilted by vertical_deg = 0.05, as in docs/optimize.md), two varied keys, three
torques (100, 200, 400 N m), --samples 16, 128 candidates: 128 x 3 x 16 = 6,144 loaded analyses of 20
positions, plus one rating (its own loaded analysis at the highest torque) per candidate, in at most
5 minutes on 2 cores with the FE tooth.

A candidate is evaluated by beveloid.optimize.evaluate.loaded_quantities, one call of the batched loaded
engine (ltca.analyze_many) for its torques and error sets: this script times that call for the three
torques and ``--sets`` error sets (drawn as the optimiser draws them) and the candidate's rating, after a
warm-up analysis (the compiled solver and the FE tooth data loaded or built), and scales it linearly to
16 sets and 128 candidates on 2 cores (candidates are independent: two workers at most halve it; the
scale assumes they do).
"""
from __future__ import annotations

import argparse
import time
import tomllib

import numpy as np

from beveloid import ltca
from beveloid.optimize import evaluate
from beveloid.optimize.request import Request, Vary
from beveloid.pair import Pair
from beveloid.spec import example_text

TORQUES = (100.0, 200.0, 400.0)
TARGET = {"candidates": 128, "samples": 16, "seconds": 300.0, "cores": 2}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tooth-model", choices=("fe", "plate"), default="fe")
    ap.add_argument("--sets", type=int, default=1, help="error sets timed per torque (default 1)")
    ap.add_argument("--positions", type=int, default=20)
    ap.add_argument("--fe-coarsen", type=float, default=1.0)
    a = ap.parse_args()
    base = tomllib.loads(example_text("case1"))  # the file as written: tooth_surface chosen per candidate
    base["misalignment"]["vertical_deg"] = 0.05
    req = Request(base=base, varies=(Vary("pinion.lead_crowning_um", 0.0, 40.0), Vary("pinion.lead_slope_um", -30, 30)),
                  torques_nm=TORQUES, weights=(0.2, 0.5, 0.3), samples=TARGET["samples"], seed=0,
                  tolerances={}, ltca=ltca.Options(positions=a.positions, tooth_model=a.tooth_model,
                                                   fe_coarsen=a.fe_coarsen))
    values = {"pinion.lead_crowning_um": 15.0, "pinion.lead_slope_um": 10.0}
    pair = Pair.from_spec(req.spec(values))
    sets = req.error_sets()[: a.sets]
    t = time.perf_counter()
    evaluate.loaded_quantities(pair, ltca.LoadCase(TORQUES[:1], errors=sets[:1]), req.ltca)
    warm = time.perf_counter() - t
    t = time.perf_counter()
    lq = evaluate.loaded_quantities(pair, ltca.LoadCase(TORQUES, errors=sets), req.ltca)
    loop = time.perf_counter() - t
    t = time.perf_counter()
    evaluate.safeties(req, pair)
    rating = time.perf_counter() - t
    n = len(TORQUES) * len(sets)
    per = loop / n
    per_candidate = per * len(TORQUES) * TARGET["samples"] + rating
    total = per_candidate * TARGET["candidates"] / TARGET["cores"]
    print(f"tooth {a.tooth_model} (fe_coarsen {a.fe_coarsen:g}), {a.positions} positions, default grid")
    print(f"warm-up analysis (solver and FE data loaded or built): {warm:.1f} s")
    print(f"{n} loaded analyses (3 torques x {len(sets)} sets): {loop:.1f} s, {per:.2f} s each;"
          f" converged positions {lq.converged_positions.min()}..{lq.converged_positions.max()} of {a.positions}")
    print(f"rating at {max(TORQUES):g} N m: {rating:.1f} s")
    print(f"one target candidate (3 x {TARGET['samples']} analyses + rating): {per_candidate:.0f} s")
    print(f"target run ({TARGET['candidates']} candidates on {TARGET['cores']} cores, perfect scaling): {total:.0f} s"
          f" = {total / 3600:.2f} h; target {TARGET['seconds']:.0f} s: {total / TARGET['seconds']:.2f} of it"
          f" ({'within' if total <= TARGET['seconds'] else 'over'})")
    print(f"check: te_peak_to_peak_urad {np.round(lq.te_peak_to_peak_urad, 3).tolist()}")


if __name__ == "__main__":
    main()

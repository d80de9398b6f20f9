"""What the rating's refinement of its maxima between positions costs (issue 57.4, docs/rating.md "The
positions check"): the rating at its defaults with and without ``refine_positions``, alternating in one
process (the FE data built or loaded once, before the timed rounds), per design and torque: the median
wall time of each, their ratio, and the refinement's added angles and rounds.

    python benchmarks/rating_refine_cost.py [--designs K,case1] [--rounds 3] [--tooth-model fe|plate]

The designs are benchmarks/rating_invariance.py's (named by letter, and ``case1``), at its torques.
"""
from __future__ import annotations

import argparse
import statistics
import time

import rating_invariance as ri


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--designs", default="K,case1", help="comma-separated letters (and case1)")
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--tooth-model", choices=("fe", "plate"), default=None)
    args = p.parse_args(argv)
    by_key = {name.split(" ")[0] if name != "case 1" else "case1": name for name in ri.TORQUES}
    names = [by_key[k.strip()] for k in args.designs.split(",") if k.strip()]
    print("| design | T (N m) | rating without (s, median) | with (s, median) | with / without | added angles | rounds |")
    print("|---|---|---|---|---|---|---|")
    for name in names:
        pair = ri._pair(name)
        for torque in ri.TORQUES[name] or ri._torques(pair):
            ri.rate(pair, torque, None, None, args.tooth_model)  # the FE data and the compiled kernels, untimed
            times = {False: [], True: []}
            check = None
            for _ in range(args.rounds):
                for refine in (False, True):
                    t0 = time.perf_counter()
                    r = ri.rate(pair, torque, None, None, args.tooth_model, refine)
                    times[refine].append(time.perf_counter() - t0)
                    if refine:
                        check = r.loaded.positions_check
            off, on = statistics.median(times[False]), statistics.median(times[True])
            print(f"| {name.split(' ')[0] if name != 'case 1' else name} | {torque:g} | {off:.2f} | {on:.2f} | "
                  f"{on / off:.2f} | {check['added_positions']} | {check['rounds']} |", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

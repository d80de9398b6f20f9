"""The sweep on threads: its time inside the parallel part and outside it, on one thread and on all.

    python benchmarks/bench_sweep_threads.py [--samples 64000] [--positions 50] [--threads N] [--rounds 2]
                                             [--simulate 16]

Not a test.  Case 1, right flank, the default error ranges, in this process with the compiled
solver: a warm-up sweep, then ``sweep.analyze`` followed by ``to_json`` (what ``beveloid sweep``
computes) with numba's thread count 1, then N (default: the cores this process may use), the pair
run ``--rounds`` times, the least time of each kept (the machine is shared: the least is the least
disturbed).  Inside: ``SweepResult.seconds``, the error sets solved and reduced to their per-set
numbers (the part on threads); outside: the rest (the engagement window, the aligned path, the
sensitivities, gathering the chunks, the statistics, the JSON dict), on one thread.  Reported: both
for each thread count, outside / the one-thread time (the goal: <= 3 %), and the speed-ups.  The
numbers of the two runs are checked equal.

``--simulate T``: for a machine with more cores than this one, the parallel part's speed-up on T
threads as its schedule allows it: the sweep's pieces for T threads run one after the other on one
thread, each timed, then dealt greedily to T threads as the pool deals them (each thread takes the
next piece when it is free).  What this leaves out is the machine's: memory bandwidth, a lower clock
with every core busy, two hardware threads sharing a core, the GIL held between pieces.
"""
from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

TIMING = ("seconds", "seconds_total", "us_per_point", "us_per_point_total")


def run(pair, samples, positions, threads):
    import numba

    from beveloid import sweep
    from beveloid.solver import Solver

    numba.set_num_threads(threads)
    t = time.perf_counter()
    res = sweep.analyze(pair, sweep.Options(samples=samples, positions=positions), solver=Solver("compiled"))
    out = res.to_json()
    whole = time.perf_counter() - t
    return res.seconds, whole - res.seconds, {k: v for k, v in out.items() if k not in TIMING}


def simulate(pair, samples, positions, threads):
    """(one-thread seconds of the pieces, their greedy makespan on ``threads``) of the sweep's parallel part."""
    from unittest import mock

    import numba

    from beveloid import sweep
    from beveloid.solver import Solver
    from beveloid.solver import threads as pool

    took = []

    def one_after_another(fn, items, _threads):
        for i, item in enumerate(items):
            t = time.perf_counter()
            result = fn(item)
            took.append(time.perf_counter() - t)
            yield i, result

    numba.set_num_threads(1)
    with mock.patch.object(pool, "count", lambda: threads), mock.patch.object(pool, "map_unordered", one_after_another):
        sweep.analyze(pair, sweep.Options(samples=samples, positions=positions), solver=Solver("compiled"))
    free = [0.0] * threads
    for d in took:  # in the order the pool hands them out
        i = free.index(min(free))
        free[i] += d
    return sum(took), max(free), len(took)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=64_000)
    ap.add_argument("--positions", type=int, default=50)
    ap.add_argument("--threads", type=int, default=len(os.sched_getaffinity(0)))
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--simulate", type=int, metavar="T", help="also the schedule's speed-up on T threads")
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args()
    import numba

    from beveloid import sweep
    from beveloid.solver import Solver
    from beveloid.pair import Pair

    pair = Pair.from_spec(Path(__file__).resolve().parents[1] / "examples" / "case1.toml")
    sweep.analyze(pair, sweep.Options(samples=200, positions=a.positions), solver=Solver("compiled"))  # numba's cache loaded
    counts = (1, min(a.threads, numba.config.NUMBA_NUM_THREADS))
    best = {n: (float("inf"), float("inf")) for n in counts}
    results = {}
    for _ in range(a.rounds):
        for n in counts:
            inside, outside, results[n] = run(pair, a.samples, a.positions, n)
            best[n] = min(best[n], (inside, outside), key=sum)
    assert results[counts[0]] == results[counts[1]], "the numbers differ between thread counts"
    one = sum(best[1])
    rows = {n: {"inside_s": i, "outside_s": o, "outside_of_one_thread": o / one, "inside_speed_up": best[1][0] / i,
                "whole_speed_up": one / (i + o)} for n, (i, o) in best.items()}
    sim = None
    if a.simulate:
        serial, makespan, pieces = simulate(pair, a.samples, a.positions, a.simulate)
        sim = {"threads": a.simulate, "pieces": pieces, "one_thread_s": serial, "makespan_s": makespan,
               "inside_speed_up": serial / makespan}
    if a.json:
        print(json.dumps({"samples": a.samples, "positions": a.positions, "threads": rows, "simulated": sim}))
        return
    print(f"sweep of case 1, {a.samples} error sets x {a.positions} positions, least of {a.rounds} rounds"
          f" (load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores)")
    print(f"{'threads':>8} {'inside s':>9} {'outside s':>10} {'outside / 1-thread time':>24} {'inside x':>9}"
          f" {'whole x':>8}")
    for n, r in rows.items():
        print(f"{n:>8} {r['inside_s']:>9.3f} {r['outside_s']:>10.3f} {100 * r['outside_of_one_thread']:>23.2f}%"
              f" {r['inside_speed_up']:>9.2f} {r['whole_speed_up']:>8.2f}")
    if sim:
        print(f"simulated on {sim['threads']} threads: {sim['pieces']} pieces, {sim['one_thread_s']:.3f} s on one thread,"
              f" makespan {sim['makespan_s']:.3f} s: inside x{sim['inside_speed_up']:.2f} (the schedule's limit)")


if __name__ == "__main__":
    main()

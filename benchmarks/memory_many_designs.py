"""Memory of one process that rates many designs one after the other (an API user's loop, optimize / explore-like).

    python benchmarks/memory_many_designs.py [--random SEED:N | --designs A,B,C] [--tooth-model plate|fe]
        [--positions 10] [--limit-mb 10000] [--tracemalloc]

Not a test.  Each design rated once (``rating.analyze`` at the first of its two line-load torques, the designs and
torques of ``benchmarks/rating_invariance.py``: ``--designs`` its letters, ``--random`` its random designs; 20 random
ones drawn with seed 5 by default), the LTCA at ``--positions`` positions (the rating's default where not given)
with ``--tooth-model`` (the rating's default where not given: the FE tooth where gmsh imports; its data from the FE
cache, computed on a miss).  After each design (the result dropped, ``gc.collect()``), one line: its seconds, the
process's resident memory (``/proc/self/status``: VmRSS, of it RssAnon and RssFile, MB), the largest so far
(``getrusage`` ru_maxrss) and the bytes that the process's FE caches hold (:func:`held_mb`: ``fe.cache._KEPT``, then
what ``ltca.model.teeth._FE_TEETH`` and ``_DEPARTURES`` hold beyond it, each array counted once, a memory map at its
mapped size) and the entries of the lru_caches keyed by a design.  ``--tracemalloc``: the 15 largest Python-side
allocations still alive at the end, by file:line (slow: about 2x).  ``--limit-mb``: the process stops itself (exit 3)
when its resident memory passes this (a machine shared by others).
"""
from __future__ import annotations

import argparse
import dataclasses
import gc
import os
import resource
import sys
import threading
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))


def memory_mb() -> dict:
    """{VmRSS, RssAnon, RssFile}: this process's resident memory now (MB, /proc/self/status)."""
    out = {}
    with open("/proc/self/status") as f:
        for line in f:
            key, _, value = line.partition(":")
            if key in ("VmRSS", "RssAnon", "RssFile"):
                out[key] = int(value.split()[0]) / 1024
    return out


def _array_bytes(obj, seen: set) -> int:
    """Bytes of the numpy arrays reachable from ``obj`` through dataclasses, dicts, sequences and attributes,
    each underlying buffer once (``seen``: ids of the buffers counted)."""
    if isinstance(obj, np.ndarray):
        base = obj
        while isinstance(base.base, np.ndarray):
            base = base.base
        if id(base) in seen:
            return 0
        seen.add(id(base))
        return base.nbytes
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return sum(_array_bytes(getattr(obj, f.name), seen) for f in dataclasses.fields(obj))
    if isinstance(obj, dict):
        return sum(_array_bytes(v, seen) for v in obj.values())
    if isinstance(obj, (tuple, list)):
        return sum(_array_bytes(v, seen) for v in obj)
    if hasattr(obj, "__dict__") and not isinstance(obj, type):
        return sum(_array_bytes(v, seen) for v in vars(obj).values())
    return 0


def held_mb() -> dict:
    """MB of arrays the FE caches of this process hold: fe.cache's kept data, then what the FE teeth and the
    departures' notes hold beyond it (an array shared counted once, where first met)."""
    from beveloid.fe import cache
    from beveloid.ltca.model import teeth

    seen: set = set()
    return {name: _array_bytes(list(held.values()), seen) / 2**20
            for name, held in (("fe.cache._KEPT", cache._KEPT), ("teeth._FE_TEETH", teeth._FE_TEETH),
                               ("teeth._DEPARTURES", teeth._DEPARTURES))}


def design_caches() -> dict:
    """{name: entries} of the lru_caches keyed by a design's geometry."""
    import importlib

    fns = {name: getattr(importlib.import_module(f"beveloid.{module}"), name) for module, name in (
        ("tca.reference", "reference_contact"), ("tca.reference", "first_touch_sign"), ("tca.backlash", "whole_pitches"),
        ("solver.patch_cover", "patch_cover"), ("ltca.mechanics.tooth_compliance", "plate_modes"),
        ("tribology.analysis", "pitch_point"))}
    return {name: fn.cache_info().currsize for name, fn in fns.items()}


def _watch(limit_mb: float) -> None:
    while True:
        if memory_mb()["VmRSS"] > limit_mb:
            print(f"stopped: resident memory over --limit-mb {limit_mb:g}", file=sys.stderr, flush=True)
            os._exit(3)
        time.sleep(0.5)


def main(argv=None) -> int:
    import rating_invariance as ri

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--random", default="5:20", metavar="SEED:N", help="N random designs of rating_invariance.py")
    p.add_argument("--designs", default=None, help="rating_invariance.py's letters instead (e.g. A,B,C)")
    p.add_argument("--tooth-model", choices=("fe", "plate"), default=None)
    p.add_argument("--positions", type=int, default=None)
    p.add_argument("--limit-mb", type=float, default=10000.0)
    p.add_argument("--tracemalloc", action="store_true")
    args = p.parse_args(argv)
    if args.designs is not None:
        by_key = {name.split(" ")[0] if name != "case 1" else "case1": name for name in ri.TORQUES}
        asked = [k.strip() for k in args.designs.split(",") if k.strip()]
        if not asked or any(k not in by_key for k in asked):
            p.error(f"--designs = {args.designs!r}: valid are {', '.join(by_key)}")
        names = [by_key[k] for k in asked]
    else:
        try:
            seed, count = (int(v) for v in args.random.split(":"))
        except ValueError:
            p.error(f"--random = {args.random!r}: valid is SEED:N, two integers (e.g. 5:20)")
        names = []
        for text in ri.random_designs(seed, count):
            name = f"R{seed}-{len(names) + 1}"
            ri.DESIGNS[name], ri.TORQUES[name] = text, None
            names.append(name)
    threading.Thread(target=_watch, args=(args.limit_mb,), daemon=True).start()
    if args.tracemalloc:
        import tracemalloc

        tracemalloc.start()
    print(f"start: {memory_mb()['VmRSS']:.0f} MB resident", flush=True)
    print("| design | T (N m) | s | resident (MB) | anon / file (MB) | largest so far (MB) | FE caches hold (MB) | "
          "lru entries |")
    print("|---|---|---|---|---|---|---|---|")
    for name in names:
        t0 = time.perf_counter()
        pair = ri._pair(name)
        torque = (ri.TORQUES[name] or ri._torques(pair))[0]
        r = ri.rate(pair, torque, None, args.positions, args.tooth_model)
        del r, pair
        gc.collect()
        m, held = memory_mb(), held_mb()
        top = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
        caches = ", ".join(f"{k} {v:.0f}" for k, v in held.items())
        entries = max(design_caches().values())
        print(f"| {name.split(' ')[0]} | {torque:g} | {time.perf_counter() - t0:.1f} | {m['VmRSS']:.0f} | "
              f"{m['RssAnon']:.0f} / {m['RssFile']:.0f} | {top:.0f} | {caches} | {entries} |", flush=True)
    if args.tracemalloc:
        for stat in tracemalloc.take_snapshot().statistics("lineno")[:15]:
            print(stat)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

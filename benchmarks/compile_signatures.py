"""numba's first compilation of the solver, and every compiled function it compiled more than once.

numba compiles a function once per argument-type signature, and a constant argument (an integer
literal, a module's constant such as ``START_COLD``) is typed ``Literal[int](value)``: a call that
passes one compiles the callee again, for that value, besides the run-time ``int64`` of its other
calls.  This script compiles what the TCA, the loaded TCA (plate tooth) and explore run, into an
empty cache folder, and prints the CPU time and each dispatcher with several signatures or a
literal argument, so that such a duplicate is seen (``--old TREE`` runs a checkout's tree the same
way in the same sitting, alternating, for the CPU ratio).

    python benchmarks/compile_signatures.py [--old TREE] [--rounds N]
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def compile_once() -> dict:
    """In this process: compile the paths, return the CPU time and the repeated signatures."""
    import numpy as np

    from beveloid import ltca, tca
    from beveloid.explore import run as explore_run
    from beveloid.pair import Pair
    from beveloid.solver import Solver

    result = {}

    def run():
        t0 = time.process_time()
        geom = Pair.from_spec(ROOT / "examples" / "case1.toml").geometry
        ref = tca.reference_contact(geom, "right")
        tca.solve_grid(geom, "right", np.zeros(5), [ref.pinion_angle], solver=Solver("compiled"))
        tca.analyze(geom, tca.Options(positions=3), solver=Solver("compiled"))
        ltca.analyze(geom, ltca.LoadCase(100.0), ltca.Options(flank="right", positions=2, pairs=1, tooth_model="plate"),
                     solver=Solver("compiled"))
        explore_run.warm_up()
        result["cpu_s"] = round(time.process_time() - t0, 1)
        seen = {}
        for name, mod in list(sys.modules.items()):
            if not name.startswith("beveloid") or mod is None:
                continue
            for attr, d in list(vars(mod).items()):
                if hasattr(d, "signatures") and hasattr(d, "py_func"):
                    seen[id(d)] = (f"{name}.{attr}", [[str(a) for a in s] for s in d.signatures])
        result["dispatchers"] = len(seen)
        result["signatures"] = sum(len(s) for _, s in seen.values())
        result["repeated"] = {n: [[a for a in s if "Literal" in a or "omitted" in a] or s for s in sigs]
                              for n, sigs in sorted(seen.values())
                              if len(sigs) > 1 or any("Literal" in a for s in sigs for a in s)}

    threading.stack_size(512 * 1024 * 1024)  # numba's typing recurses deeply
    t = threading.Thread(target=run)
    t.start()
    t.join()
    return result


def in_subprocess(tree: Path) -> dict:
    with tempfile.TemporaryDirectory(prefix="compile_sigs_") as tmp:
        env = dict(os.environ, BEVELOID_CACHE_DIR=tmp, PYTHONPATH=str(tree))
        env.pop("NUMBA_CACHE_DIR", None)
        proc = subprocess.run([sys.executable, str(Path(__file__).resolve()), "--here"], cwd=tree, env=env,
                              capture_output=True, text=True)
    if proc.returncode != 0:
        raise SystemExit(f"{tree}: {proc.stderr[-2000:]}")
    return json.loads(proc.stdout.splitlines()[-1])


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--old", type=Path, help="another checkout's tree, compiled alternately with this one")
    p.add_argument("--rounds", type=int, default=1)
    p.add_argument("--here", action="store_true", help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    if args.here:
        print(json.dumps(compile_once()))
        return 0
    trees = [("new", ROOT)] + ([("old", args.old.resolve())] if args.old else [])
    cpu = {name: [] for name, _ in trees}
    for _ in range(args.rounds):
        for name, tree in trees:
            r = in_subprocess(tree)
            cpu[name].append(r["cpu_s"])
            print(f"{name} ({tree}): {r['cpu_s']} s CPU (load {os.getloadavg()[0]:.2f}), {r['dispatchers']} "
                  f"dispatchers, {r['signatures']} signatures", flush=True)
            for fn, sigs in r["repeated"].items():
                print(f"    {fn}: {len(sigs)} signature(s): {'; '.join(', '.join(s) for s in sigs)[:300]}")
    if args.old:
        print(f"CPU new / old: {sum(cpu['new']) / sum(cpu['old']):.3f} ({args.rounds} round(s))")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

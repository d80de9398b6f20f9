"""Where the batched loaded engine's CPU time goes: one ``ltca.analyze_many`` call split into its parts.

    python benchmarks/ltca_time_split.py [SPEC | --case case1] [--torques-nm 100,200,400] [--sets 8]
                                         [--tooth-model fe] [--positions 20] [--repeats 3] [--convergence]

Not a test.  One BLAS thread; one warm-up call (numba's cache, the FE data); then the call with the
least process CPU time of ``--repeats``, its parts timed by wrapping the engine's functions (CPU time
of each, inclusive): the unloaded gaps (``ltca.model.gaps.grid_gaps``, the gap Newtons of every pass), the
compliance tables (``ltca.passes.cycle.compliance_tables``: half-space tables, the teeth's line
compliances), the contact solve of every pass (``ltca.passes.cycle.solve_many`` less the two before: the
dense blocks and the active set), the root stresses (``ltca.model.teeth.root_stresses``) and the rest (the rigid reference, grids, results).  The
error sets: none, then ``--sets - 1`` small ones, as benchmarks/bench_ltca.py draws them.  The
default (case 1 tilted by 0.05 deg, three torques, 8 sets, no convergence indicator) is one call of
``beveloid optimize``'s candidate (docs/optimize.md section 6: the candidate makes two);
``--convergence``: with the indicator, as ``ltca.analyze`` runs by default.  Also printed: the mean
active-set iterations a converged position of each call of the contact solve, in the order the passes
make them.
"""
from __future__ import annotations

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_v] = "1"

import argparse  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_ltca import error_sets  # noqa: E402

PARTS = (("gaps", "beveloid.ltca.passes.cycle", "gaps.grid_gaps"), ("blocks", "beveloid.ltca.passes.cycle", "compliance_tables"),
         ("passes", "beveloid.ltca.passes.analysis", "solve_many"), ("root", "beveloid.ltca.passes.analysis", "root_stresses"))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("spec", nargs="?", help="a spec file (default: case 1 tilted by vertical_deg = 0.05)")
    ap.add_argument("--case", default="case1")
    ap.add_argument("--torques-nm", default="100,200,400")
    ap.add_argument("--sets", type=int, default=8)
    ap.add_argument("--tooth-model", choices=("fe", "plate"), default="fe")
    ap.add_argument("--positions", type=int, default=20)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--convergence", action="store_true",
                    help="with the grid-convergence indicator (ltca.analyze's default; the tolerance box and optimize "
                         "leave it out: ltca.studies.box_results)")
    a = ap.parse_args()

    import importlib

    from beveloid import ltca
    from beveloid.pair import Pair
    from beveloid.solver import Solver
    from beveloid.spec import example_text

    if a.spec:
        pair, name = Pair.from_spec(a.spec), a.spec
    else:
        text = example_text(a.case).replace("vertical_deg = 0.0 ", "vertical_deg = 0.05", 1)
        path = Path(os.environ.get("TMPDIR", "/tmp")) / f"{a.case}_tilted.toml"
        path.write_text(text)
        pair, name = Pair.from_spec(str(path)), f"{a.case} tilted by 0.05 deg"
    torques = [float(t) for t in a.torques_nm.split(",")]
    sets = error_sets(a.sets)
    options = ltca.Options(positions=a.positions, tooth_model=a.tooth_model)

    spent, iterations = {}, []
    solve_many = importlib.import_module("beveloid.ltca.passes.analysis").solve_many

    def counted(*args, **kw):  # the active-set iterations of each call of the contact solve
        sols = solve_many(*args, **kw)
        its = np.concatenate([s.iterations[s.converged] for s in sols])
        iterations.append((its.size, float(its.mean()) if its.size else 0.0))
        return sols
    importlib.import_module("beveloid.ltca.passes.analysis").solve_many = counted
    for key, module, attr in PARTS:  # wrap each part where the engine looks it up
        mod = importlib.import_module(module)
        owner, name_ = (getattr(mod, attr.split(".")[0]), attr.split(".")[1]) if "." in attr else (mod, attr)
        fn = getattr(owner, name_)

        def timed(*args, _fn=fn, _key=key, **kw):
            t = time.process_time()
            try:
                return _fn(*args, **kw)
            finally:
                spent[_key] = spent.get(_key, 0.0) + time.process_time() - t
        setattr(owner, name_, timed)

    def call():
        return ltca.analyze_many(pair, ltca.LoadCase(torques, errors=sets), options, solver=Solver(),
                                 convergence=a.convergence)

    call()
    best = None
    for _ in range(a.repeats):
        spent.clear()
        iterations.clear()
        t = time.process_time()
        call()
        total = time.process_time() - t
        if best is None or total < best[0]:
            best = (total, dict(spent), list(iterations))
    total, s, its = best
    contact = s["passes"] - s["gaps"] - s["blocks"]
    rows = [("unloaded gaps (gap Newtons)", s["gaps"]), ("compliance tables", s["blocks"]),
            ("contact solve (blocks, active set)", contact), ("root stresses", s["root"]),
            ("the rest", total - s["passes"] - s["root"])]
    cases = len(torques) * len(sets)
    print(f"{name}: {a.tooth_model} tooth, {a.positions} positions x {len(torques)} torques x {len(sets)} error sets "
          f"({cases} analyses) in one call, {'with' if a.convergence else 'without'} the convergence indicator: "
          f"{total:.3f} CPU s ({1e3 * total / cases:.1f} ms an analysis)")
    for label, v in rows:
        print(f"  {label:30s} {v:7.3f} s  {100 * v / total:5.1f} %")
    print("  active-set iterations a converged position, each call of the contact solve in order (positions): "
          + ", ".join(f"{m:.2f} ({n})" for n, m in its))


if __name__ == "__main__":
    main()

"""LTCA throughput: loaded positions per CPU second of the batched engine against a reference tree's
per-position path, in one run, with the results compared.

    python benchmarks/bench_ltca.py [--reference COMMIT] [--case case1] [--torque-nm 200] [--positions 20]
                                    [--sets 4] [--tooth-model fe] [--repeats 3] [--rounds 2] [--json]

Not a test.  The reference is ``git archive COMMIT`` unpacked into a temporary folder and put first on
PYTHONPATH of a child process, which runs ``ltca.analyze(pair, Options(...))`` once per error set (its
per-position path); a second child runs this tree's ``ltca.analyze_many`` over the same error sets in
one call.  Both: one BLAS thread, one warm-up (numba's cache, the FE data cache), then the least
process CPU time of ``--repeats``, the children run ``--rounds`` times alternately (the least again:
on a shared machine the CPU time of the same work drifts with the load).  The error sets: none, then ``--sets - 1`` small ones (dx, dy, dz up
to 0.02 mm, tilts up to 0.01 deg).  Reported: positions per CPU second of each, their ratio, and the
largest relative difference (max |a - b| / max |a| per quantity) over loaded TE, pair loads, peak
pressures, mesh stiffness and root stresses.  Default reference: the commit before the batched engine.
"""
from __future__ import annotations

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_v] = "1"

import argparse  # noqa: E402
import json  # noqa: E402
import math  # noqa: E402
import pickle  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

REFERENCE = "691f171"  # the tree before the batched engine (per-position solve, per-node eigvalsh)
FIELDS = ("loaded_te", "pair_load_n", "pair_max_pressure_mpa", "mesh_stiffness_n_per_um")
ROOT = ("pair_root_stress_mpa", "pair_root_compressive_stress_mpa")


def error_sets(k: int) -> np.ndarray:
    out = [np.zeros(5)]
    rng = np.random.default_rng(7)
    for _ in range(k - 1):
        out.append(np.concatenate([rng.uniform(-0.02, 0.02, 3), np.radians(rng.uniform(-0.01, 0.01, 2))]))
    return np.array(out)


def worker(a):
    from beveloid import ltca
    from beveloid.pair import Pair

    pair = Pair.example(a.case)
    sets = error_sets(a.sets)
    opts = dict(positions=a.positions, tooth_model=a.tooth_model)

    def run():
        if hasattr(ltca, "LoadCase"):  # the load case apart from the options (issue 56)
            if a.worker == "reference":
                return [ltca.analyze(pair, ltca.LoadCase(a.torque_nm, errors=tuple(e)), ltca.Options(**opts))
                        for e in sets]
            batch = ltca.analyze_many(pair, ltca.LoadCase(a.torque_nm, errors=sets), ltca.Options(**opts))
            return [row[0] for row in batch.results]
        opts["torque_nm"] = a.torque_nm
        if a.worker == "reference":
            return [ltca.analyze(pair, ltca.Options(errors=tuple(e), **opts)) for e in sets]
        batch = ltca.analyze_many(pair, ltca.Options(**opts), error_sets=sets)
        return [row[0] for row in batch.results]

    results = run()  # warm-up: numba's cache, the FE data
    times = []
    for _ in range(a.repeats):
        t = time.process_time()
        run()
        times.append(time.process_time() - t)
    keep = [{**{f: np.asarray(getattr(r, f)) for f in FIELDS}, **{f: dict(getattr(r, f)) for f in ROOT},
             "converged": np.asarray(r.converged)} for r in results]
    with open(a.out, "wb") as fh:
        pickle.dump({"cpu_s": min(times), "results": keep}, fh)


def relative(a, b) -> float:
    a, b = np.asarray(a, float), np.asarray(b, float)
    if not np.array_equal(np.isfinite(a), np.isfinite(b)):
        return math.inf
    m = np.isfinite(a)
    return float(np.max(np.abs(a[m] - b[m])) / max(np.max(np.abs(a[m])), 1e-300)) if m.any() else 0.0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--reference", default=REFERENCE)
    ap.add_argument("--case", default="case1")
    ap.add_argument("--torque-nm", type=float, default=200.0)
    ap.add_argument("--positions", type=int, default=20)
    ap.add_argument("--sets", type=int, default=4)
    ap.add_argument("--tooth-model", default="fe")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--worker", choices=("reference", "batched"), help=argparse.SUPPRESS)
    ap.add_argument("--out", help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.worker:
        return worker(a)
    here = Path(__file__).resolve().parents[1]
    args = ["--case", a.case, "--torque-nm", str(a.torque_nm), "--positions", str(a.positions), "--sets",
            str(a.sets), "--tooth-model", a.tooth_model, "--repeats", str(a.repeats)]
    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        ref = Path(tmp) / "reference"
        ref.mkdir()
        archive = subprocess.run(["git", "-C", str(here), "archive", a.reference], check=True, capture_output=True)
        subprocess.run(["tar", "-x", "-C", str(ref)], input=archive.stdout, check=True)
        for _ in range(a.rounds):  # alternated: a busy machine's drift falls on both alike
            for name, path in (("reference", ref), ("batched", here)):
                env = dict(os.environ, PYTHONPATH=str(path))
                res = Path(tmp) / f"{name}.pkl"
                subprocess.run([sys.executable, __file__, "--worker", name, "--out", str(res), *args], check=True,
                               env=env, cwd=tmp)
                with open(res, "rb") as fh:
                    got = pickle.load(fh)
                if name not in out or got["cpu_s"] < out[name]["cpu_s"]:
                    out[name] = got
    n = a.positions * a.sets
    rate = {k: n / v["cpu_s"] for k, v in out.items()}
    diff = 0.0
    for r0, r1 in zip(out["reference"]["results"], out["batched"]["results"]):
        diff = max([diff] + [relative(r0[f], r1[f]) for f in FIELDS]
                   + [relative(r0[f][m], r1[f][m]) for f in ROOT for m in r0[f]])
    report = {"case": a.case, "torque_nm": a.torque_nm, "positions": a.positions, "error_sets": a.sets,
              "tooth_model": a.tooth_model, "reference": a.reference,
              "reference_cpu_s": out["reference"]["cpu_s"], "batched_cpu_s": out["batched"]["cpu_s"],
              "reference_positions_per_cpu_s": rate["reference"], "batched_positions_per_cpu_s": rate["batched"],
              "speedup": rate["batched"] / rate["reference"], "max_relative_difference": diff,
              "all_converged": bool(all(np.all(r["converged"]) for r in out["batched"]["results"]))}
    if a.json:
        print(json.dumps(report))
    else:
        print(f"LTCA {a.case}, {a.torque_nm:g} N m, {a.tooth_model} tooth, {a.positions} positions x {a.sets} error "
              f"sets: reference {a.reference} {report['reference_cpu_s']:.2f} CPU s "
              f"({rate['reference']:.1f} positions/CPU s), batched {report['batched_cpu_s']:.3f} CPU s "
              f"({rate['batched']:.1f} positions/CPU s): {report['speedup']:.1f} x; largest relative difference "
              f"{diff:.1e}; all converged {report['all_converged']}")


if __name__ == "__main__":
    main()

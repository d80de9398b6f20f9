"""What the tribology costs (issue 58): `beveloid ltca` with and without `--speed-rpm`, and the
4-torque x 4-speed efficiency map against the 4-torque map without it, timed in one run, interleaved.

    python benchmarks/bench_tribology.py                   # plate tooth, 5 repeats
    python benchmarks/bench_tribology.py --tooth-model fe  # the default FE tooth (its FE data cached first)
    python benchmarks/bench_tribology.py --json

Not a test.  Each measurement is the command run in this process (``beveloid.cli.main``, stdout
captured) on the paper's case1 (crossed beveloid) with a mineral ISO VG 100 at 70 C and Ra 0.5 um
added; the four variants run in turn within every repeat, so that the machine's load falls on all of
them alike, and the medians are compared.  A warm-up run of each variant first (the compiled kernels
and the FE data are loaded once).
"""
from __future__ import annotations

import argparse
import contextlib
import io
import json
import os
import statistics
import sys
import tempfile
import time

TORQUES = "50,100,200,400"
SPEEDS = "500,1000,2000,4000"
LUBRICANT = """
[lubricant]
iso_vg = 100
base_oil = "mineral"
temperature_c = 70.0
fzg_load_stage = 12
"""


def case_file(folder):
    """case1 with Ra 0.5 um on both members and the oil of LUBRICANT, written as a TOML file."""
    from beveloid.spec import load_example, spec_to_dict

    data = spec_to_dict(load_example("case1"))
    lines = []
    for section, keys in data.items():
        if section == "lubricant":
            continue
        if section in ("pinion", "gear"):
            keys = dict(keys, roughness_ra_um=0.5)
        lines.append(f"[{section}]")
        lines += [f"{k} = {json.dumps(v)}" for k, v in keys.items()]
    path = os.path.join(folder, "case1_oil.toml")
    with open(path, "w") as fh:
        fh.write("\n".join(lines) + "\n" + LUBRICANT)
    return path


def run_cli(argv):
    from beveloid import cli

    t0 = time.perf_counter()
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        rc = cli.main(argv)
    if rc != 0:
        raise SystemExit(f"beveloid {' '.join(argv)} exited {rc}")
    return time.perf_counter() - t0


def split(spec_path, tooth_model):
    """In this process: the 4 torques' LTCA (one analyze_many), the tribology of its 4 x 4 map, and of one
    torque at one speed (seconds)."""
    from beveloid import ltca, tribology
    from beveloid.pair import Pair
    from beveloid.spec import load_spec

    pair = Pair.from_spec(load_spec(spec_path))
    torques = [float(t) for t in TORQUES.split(",")]
    options = ltca.Options(tooth_model=tooth_model)
    t0 = time.perf_counter()
    results = ltca.analyze_many(pair, ltca.LoadCase(tuple(torques)), options).results[0]
    t1 = time.perf_counter()
    tribology.efficiency_map(results, pair, [float(s) for s in SPEEDS.split(",")])
    t2 = time.perf_counter()
    tribology.efficiency_map(results[:1], pair, [1000.0])
    t3 = time.perf_counter()
    return {"ltca 4 torques (analyze_many)": t1 - t0, "tribology 4 x 4 (efficiency_map)": t2 - t1,
            "tribology 1 x 1": t3 - t2}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--tooth-model", choices=("plate", "fe"), default="plate")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        spec = case_file(tmp)
        base = ["ltca", spec, "--tooth-model", args.tooth_model, "--json"]
        variants = {
            "ltca 200 N m": base + ["--torque-nm", "200"],
            "ltca 200 N m + tribology 1000 rpm": base + ["--torque-nm", "200", "--speed-rpm", "1000"],
            "ltca 4 torques": base + ["--torque-nm", TORQUES],
            "ltca 4 torques x 4 speeds": base + ["--torque-nm", TORQUES, "--speed-rpm", SPEEDS],
        }
        for argv in variants.values():  # warm-up: compiled code, FE data
            run_cli(argv)
        times = {k: [] for k in variants}
        parts = {"ltca 4 torques (analyze_many)": [], "tribology 4 x 4 (efficiency_map)": [],
                 "tribology 1 x 1": []}
        for _ in range(args.repeats):
            for k, argv in variants.items():
                times[k].append(run_cli(argv))
            for k, v in split(spec, args.tooth_model).items():
                parts[k].append(v)
    med = {k: statistics.median(v) for k, v in times.items()}
    part = {k: statistics.median(v) for k, v in parts.items()}
    out = {"tooth_model": args.tooth_model, "repeats": args.repeats, "load_1min": os.getloadavg()[0],
           "median_s": med,
           "tribology_over_ltca": med["ltca 200 N m + tribology 1000 rpm"] / med["ltca 200 N m"],
           "map_over_torques": med["ltca 4 torques x 4 speeds"] / med["ltca 4 torques"],
           "in_process_s": part,
           "tribology_share_of_ltca": part["tribology 1 x 1"] / (part["ltca 4 torques (analyze_many)"] / 4),
           "map_share_of_ltca": part["tribology 4 x 4 (efficiency_map)"] / part["ltca 4 torques (analyze_many)"]}
    if args.json:
        json.dump(out, sys.stdout, indent=1)
        print()
        return
    print(f"tooth model {args.tooth_model}, {args.repeats} interleaved repeats, load {out['load_1min']:.2f}")
    for k, v in med.items():
        print(f"  {k:<36} median {v:7.3f} s  (runs {', '.join(f'{x:.2f}' for x in times[k])})")
    print(f"ltca + tribology / ltca: {out['tribology_over_ltca']:.3f} (issue 58: at most 1.15)")
    print(f"4 x 4 efficiency map / 4-torque map: {out['map_over_torques']:.3f} (issue 58: at most 1.3)")
    print("in process (medians): " + ", ".join(f"{k} {v:.3f} s" for k, v in part.items()))
    print(f"  the tribology of one torque and speed / one torque's LTCA: {out['tribology_share_of_ltca']:.3f}; "
          f"the 4 x 4 map's tribology / the 4 torques' LTCA: {out['map_share_of_ltca']:.3f}")


if __name__ == "__main__":
    main()

"""FE (CalculiX) against the LTCA, the runs of docs/validation.md "Full-contact FE check (issue 33)".

Each run is ``beveloid.fecheck.check.fe_check`` (what ``beveloid fe-check`` runs) on one design,
flank, torque and refinement; the table gives per quantity FE / LTCA.  Results are appended as
JSON lines to OUT (default fe_check_runs.jsonl) so that a long series can be resumed.

    python benchmarks/fe_check_validation.py [--designs case1:right,case2:right] [--torques 100,400]
        [--refinements 1,2] [--coarsen 1.0] [--tooth-model fe|plate] [--out fe_check_runs.jsonl] [--table-only]
"""
import argparse
import json
import sys
import time
from pathlib import Path

from beveloid.fecheck.check import CheckOptions, fe_check
from beveloid.pair import Pair


def run(design, flank, torque, refinement, coarsen, tooth_model=None):
    pair = Pair.example(design)
    t0 = time.perf_counter()
    out = fe_check(pair, CheckOptions(torque_nm=torque, flank=flank, refinement=refinement, coarsen=coarsen,
                                      ltca_tooth_model=tooth_model),
                   progress=lambda s: print(s, file=sys.stderr, flush=True) if not s.startswith("ccx") else None)
    out.update(design=design, total_s=time.perf_counter() - t0, coarsen=coarsen)
    return out


def fmt(v, f):
    return "-" if v is None else format(v, f)


def table(rows):
    lines = ["| design, flank | T (N m) | N | elements / DOF | ccx (s) | pair loads FE / LTCA (N) | peak p FE / LTCA (MPa)"
             " | area FE / LTCA (mm²) | loaded TE FE / LTCA (µrad), unloaded | root σ1 pinion / gear FE (MPa)"
             " | moment FE / LTCA (N m) |", "|" + "---|" * 11]
    for r in rows:
        c, lt = r["calculix"], r["ltca"]
        pairs = lambda key, f: "; ".join(f"{fmt(a, f)} / {fmt(b, f)}" for a, b in zip(c[key], lt[key])  # noqa: E731
                                         if (a or 0) > 0 or (b or 0) > 0)
        lines.append(
            f"| {r['design']} {r['flank']} (pos. {r['position']}, {r.get('ltca_tooth_model', 'plate')}) | {r['torque_nm']:g} | {r['refinement']}"
            f"{'' if r.get('coarsen', 1.0) == 1.0 else ' (x' + format(r['coarsen'], 'g') + ')'} | {r['elements']} / {r['dof']}"
            f" | {r['calculix_wall_s']:.0f} | {pairs('pair_normal_load_n', '.0f')} | {pairs('pair_max_pressure_mpa', '.0f')}"
            f" | {pairs('contact_area_mm2', '.1f')} | {fmt(c['loaded_transmission_error_urad'], '.1f')} / "
            f"{fmt(lt['loaded_transmission_error_urad'], '.1f')}, {r['unloaded_transmission_error_urad']:.1f}"
            f" | {fmt(c['root_stress_max_mpa']['pinion'], '.0f')} / {fmt(c['root_stress_max_mpa']['gear'], '.0f')}"
            f" | {fmt(c['moment_about_pinion_axis_nm'], '.2f')} / {fmt(lt['moment_about_pinion_axis_nm'], '.2f')} |")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--designs", default="case1:right,case2:right")
    ap.add_argument("--torques", default="100,400")
    ap.add_argument("--refinements", default="1,2")
    ap.add_argument("--coarsen", type=float, default=1.0)
    ap.add_argument("--out", default="fe_check_runs.jsonl")
    ap.add_argument("--table-only", action="store_true")
    ap.add_argument("--tooth-model", default=None, help="the LTCA's tooth model (fe, plate; default: its default)")
    a = ap.parse_args()
    path = Path(a.out)
    done = [json.loads(s) for s in path.read_text().splitlines()] if path.exists() else []
    if not a.table_only:
        for item in a.designs.split(","):
            design, flank = item.split(":")
            for t in map(float, a.torques.split(",")):
                for n in map(int, a.refinements.split(",")):
                    key = (design, flank, t, n, a.coarsen)
                    if any((r["design"], r["flank"], r["torque_nm"], r["refinement"], r.get("coarsen", 1.0)) == key
                           for r in done):
                        continue
                    r = run(design, flank, t, n, a.coarsen, a.tooth_model)
                    done.append(r)
                    with path.open("a") as fh:
                        fh.write(json.dumps(r, allow_nan=False) + "\n")
                    print(table([r]), flush=True)
    print(table(done))


if __name__ == "__main__":
    main()

"""Do two checkouts give the same bits?  design() on random specs and explore's rows on a grid.

    git worktree add --detach /tmp/before REV
    python benchmarks/compare_checkouts.py /tmp/before [--specs 1000] [--seed 7] [--designs 256] [--with-tooth]

Runs each checkout in its own process (its own beveloid): ``design()`` of ``--specs`` random specs
about case 1 and case 2 (offset, shaft angle, teeth, profile shift, cone and helix angles, face
width, reference section: most are refused) plus the two examples and their indirect design, every
field's repr or the refusal's line; and every column of ``explore.rows.compute`` (without the
whole-tooth checks, which the older checkout may lack) on benchmarks/bench_explore.py's grid of
``--designs``.  With ``--with-tooth`` the rows are computed with the whole-tooth checks (status,
tooth_status, reason: both checkouts must have them), on that grid and on two more whose designs are
often undercut or pointed: pinion x gear face width (50-1000 x 60-1000 mm, 40 x 6) and a Latin
hypercube of 1500 designs over nine keys.  Prints how many differ.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys

_DESIGNS = r'''
import copy, dataclasses, json, os, sys
sys.path.insert(0, os.getcwd())
import numpy as np
from beveloid.design import DesignError, design, indirect_design
from beveloid.spec import SpecError, load_example, spec_from_dict, spec_to_dict

def flat(r):
    d = {}
    for f in dataclasses.fields(r):
        v = getattr(r, f.name)
        if f.name == "spec":
            continue
        if dataclasses.is_dataclass(v):
            d.update({f"{f.name}.{g.name}": repr(getattr(v, g.name)) for g in dataclasses.fields(v)})
        else:
            d[f.name] = repr(v)
    return d

n, seed = int(sys.argv[1]), int(sys.argv[2])
rng = np.random.default_rng(seed)
out = []
bases = [spec_to_dict(load_example("case1")), spec_to_dict(load_example("case2"))]
for i in range(n):
    d = copy.deepcopy(bases[i % 2])
    if i >= 2:
        d["pair"]["offset_mm"] = float(rng.uniform(1, 400))
        d["pair"]["shaft_angle_deg"] = float(rng.uniform(5, 60))
        d["pinion"]["profile_shift"] = float(rng.uniform(-1, 1))
        d["pinion"]["teeth"] = int(rng.integers(8, 60))
        d["gear"]["teeth"] = int(rng.integers(10, 90))
        d["pinion"]["cone_angle_deg"] = float(rng.uniform(-10, 10))
        d["gear"]["cone_angle_deg"] = float(rng.uniform(-10, 10))
        d["pinion"]["helix_angle_deg"] = float(rng.uniform(-40, 40))
        d["pinion"]["face_width_mm"] = float(rng.uniform(5, 1000))
        d["pinion"]["reference_section_offset_mm"] = float(rng.uniform(-20, 20))
    try:
        spec = spec_from_dict(d)
    except SpecError as e:
        out.append({"spec_error": str(e)}); continue
    try:
        out.append(flat(design(spec)))
    except DesignError as e:
        out.append({"refused": str(e)})
for b in bases:
    r = design(spec_from_dict(b))
    out.append(flat(indirect_design(spec_from_dict(b), r.working_normal_pressure_angle, r.pinion.working_cone_angle,
                                    r.gear.working_cone_angle, r.pinion.working_helix_angle)))
print(json.dumps(out))
'''

_ROWS = r'''
import hashlib, json, os, sys
sys.path[:0] = [os.getcwd(), os.path.join(os.getcwd(), "benchmarks")]
import numpy as np
from bench_explore import _plan
from beveloid.explore import rows
from beveloid.sweep import DEFAULT_RANGES
from beveloid.explore.grid import Plan, parse_vary
from beveloid.spec import load_example, spec_to_dict
with_tooth = sys.argv[2] == "1"
plans = {"grid": _plan(int(sys.argv[1]))}
if with_tooth:
    base = spec_to_dict(load_example("case1"))
    plans["face"] = Plan(base, (parse_vary("pinion.face_width_mm=50:1000:40"), parse_vary("gear.face_width_mm=60:1000:6")))
    plans["lhs"] = Plan(base, tuple(parse_vary(v) for v in (
        "pinion.profile_shift=-1:1:2", "pinion.face_width_mm=10:900:2", "pinion.teeth=8:60:53", "gear.teeth=10:80:71",
        "pinion.addendum_coefficient=0.6:1.2:2", "pinion.cone_angle_deg=-10:10:2", "gear.cone_angle_deg=-10:10:2",
        "pinion.cutter_tip_radius_coefficient=0:0.4:2", "pair.offset_mm=100:400:2")), samples=1500, seed=3)
kw = {} if with_tooth or "tooth_checks" not in rows.compute.__code__.co_varnames else {"tooth_checks": False}
out = {}
for name, plan in plans.items():
    parts = [rows.compute(plan, s, min(plan.count, s + 256), DEFAULT_RANGES, **kw) for s in range(0, plan.count, 256)]
    for k in parts[0]:
        v = np.concatenate([np.asarray(p[k]) for p in parts])
        key = k if name == "grid" else f"{name}/{k}"
        out[key] = hashlib.sha1("|".join(map(str, v)).encode() if v.dtype == object else v.tobytes()).hexdigest()
print(json.dumps(out))
'''


def _run(code, where, *args):
    out = subprocess.run([sys.executable, "-c", code, *map(str, args)], cwd=where, check=True, capture_output=True,
                         text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("before", metavar="CHECKOUT")
    ap.add_argument("--specs", type=int, default=1000)
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--designs", type=int, default=256)
    ap.add_argument("--with-tooth", action="store_true", help="rows with the whole-tooth checks, on three grids")
    a = ap.parse_args(argv)
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    old, new = (_run(_DESIGNS, w, a.specs, a.seed) for w in (a.before, here))
    feasible = sum(len(x) > 1 for x in old)
    print(f"design(): {len(old)} specs ({feasible} designed, the rest refused), "
          f"{sum(x != y for x, y in zip(old, new))} differ (fields' reprs or refusal lines)")
    old, new = (_run(_ROWS, w, a.designs, int(a.with_tooth)) for w in (a.before, here))
    common = sorted(set(old) & set(new))
    grids = f"{a.designs}-design grid" + (", face widths, hypercube; with the whole-tooth checks" if a.with_tooth else "")
    print(f"explore rows ({grids}): {len(common)} common columns, "
          f"{sum(old[k] != new[k] for k in common)} differ; only before: {sorted(set(old) - set(new))},"
          f" only after: {sorted(set(new) - set(old))}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

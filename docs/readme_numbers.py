"""The numbers the README and the docs pages quote, and where each is quoted.

    python docs/readme_numbers.py             # check: every quote below is in its page (exit 1 if not)
    python docs/readme_numbers.py --print     # the quotes as they should read now
    python docs/readme_numbers.py --record    # rerun the expensive sources, rewrite docs/numbers.json
    python docs/readme_numbers.py --record rating,fe_tooth   # only these groups (the others are kept)
    python docs/readme_numbers.py --record fe_check --fe-check-runs RUNS.jsonl

Two kinds of numbers:

* cheap ones, computed here each time (constants of the package, one TCA of case 1: ~1 s);
* expensive ones, recorded in ``docs/numbers.json`` by ``--record``, one group each (:data:`GROUPS`),
  which runs the commands named there: ``explore`` (the worked exploration of docs/explore.md: 216
  designs with a Monte Carlo sweep each; it copies the exploration's figures into docs/images/),
  ``verify`` (``beveloid verify --json``), ``paper`` (``beveloid paper``: the micro-geometry study's
  pressures that docs/input.md quotes), ``rating`` (docs/validation.md 10: the rating of case 1 and
  case 2 at 1500 N m with the FE tooth, a few minutes with the FE data computed), ``fe_tooth``
  (docs/loaded_contact.md 9.7: ``python -m benchmarks.bench_fe_tooth compare``), ``fe_check``
  (docs/validation.md 11: CalculiX runs of ``benchmarks/fe_check_validation.py``, tens of minutes each
  on 2 cores: ``--record fe_check`` copies them from the runs file that script wrote, ``--fe-check-runs``),
  ``fe_sectors`` (docs/validation.md 11.0: ``python benchmarks/fe_check_sector_bcs.py``, minutes),
  ``ltca_tables`` (docs/validation.md 7.2 and 7.5: ``benchmarks/ltca_grid_convergence.py`` and
  ``benchmarks/ltca_paper_loaded.py``, a minute or two with the FE data cached).
  A page quoting them must match the JSON; after a change that moves them, rerun ``--record GROUP``
  and paste what ``--print`` shows.

Drift: a quote of an expensive number matches the JSON, not the code, so each FE group also records a
**canary** (:func:`fe_canary`): the same analyses on the suite's coarse FE tooth (case 1, every element
size x 3, a few positions), which tests/fe/test_fe_docs_canary.py recomputes from the session's coarse
FE data (about 3 s) and compares with the record: a change of the code that moves the FE tooth, the
LTCA or the rating moves the canary and fails the test until the group is recorded again.  The CalculiX
numbers (``fe_check``), the sectors' (``fe_sectors``) and the LTCA tables of validation 7
(``ltca_tables``) have no canary of their own: the test checks that every quoted row is the record's,
formatted as the benchmark script formats it (the ``fe_tooth`` and ``rating`` canaries cover the FE
tooth and the LTCA that ``ltca_tables`` runs).

tests/docs/test_docs_numbers.py checks that every quote is in its page, with the cheap numbers
computed now and the expensive ones from the JSON.
"""
from __future__ import annotations

import argparse
import csv
import json
import math
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
RECORD = ROOT / "docs" / "numbers.json"

#: the worked example of docs/explore.md, exactly as the page shows it (FILE relative to the checkout)
EXPLORE_ARGS = ["explore", "examples/case1.toml", "--vary", "pinion.cone_angle_deg=0.25:4.5:18",
                "--vary", "pinion.helix_angle_deg=12:34:12",
                "--tolerances", "dx=0.05,dy=0.05,dz=0.05,vertical=0.02,horizontal=0.02",
                "--mc", "40", "--workers", "2"]


#: the largest helix angle of the grid at the smallest cone angle whose design is `ok` (the end of
#: the trade-off the page follows; 30 deg is undercut since explore runs the whole-tooth checks)
HIGH_HELIX_DEG = 28


def _benchmark(name: str):
    """benchmarks/<name>.py, imported as ``benchmarks.<name>`` with the checkout's folder on ``sys.path`` only
    while it is imported: the quotes are also computed inside the test suite (tests/docs/test_docs_numbers.py),
    whose worker processes started later (``beveloid.parallel``'s spawned workers) inherit the test process's
    ``sys.path``; with the checkout first on it they imported the checkout's beveloid instead of the installed
    one and compiled the solver afresh, into the checkout (~90-125 s of CPU each, seen in the README's test
    command on a fresh install)."""
    import importlib

    saved = list(sys.path)
    sys.path.insert(0, str(ROOT))
    try:
        return importlib.import_module(f"benchmarks.{name}")
    finally:
        sys.path[:] = saved


def cheap_numbers() -> dict:
    """Numbers computed from the package now (about a second)."""

    from beveloid import sweep, tca
    from beveloid.pair import Pair

    res = tca.analyze(Pair.example("case1"), tca.Options(positions=50))
    te_ptp_urad = max(fr.te_peak_to_peak for fr in res.flanks.values()) * 1e6
    return {
        "max_contact_points": sweep.MAX_CONTACT_POINTS,
        "approach_um": tca.Options().approach_mm * 1e3,
        "sweep_chunk": sweep.Options().chunk,
        "case1_backlash_um": abs(res.backlash_um),
        "case1_te_ptp_urad": te_ptp_urad,
    }


def _rows(folder: Path) -> list[dict]:
    with open(folder / "explore.csv", newline="") as f:
        return list(csv.DictReader(f))


def _f(row, key):
    v = row.get(key, "")
    return float(v) if v not in ("", None) else float("nan")


def explore_numbers(folder: Path) -> dict:
    """The worked example's numbers from its output folder."""
    summ = json.loads((folder / "summary.json").read_text())
    rows = _rows(folder)
    cone, helix = "pinion.cone_angle_deg", "pinion.helix_angle_deg"

    def at(c, h):
        return next(r for r in rows if math.isclose(_f(r, cone), c) and math.isclose(_f(r, helix), h))

    base = summ["base_design"]
    pareto = summ["pareto_designs"]
    alt, lo, hi = at(0.25, 22), at(0.25, 12), at(0.25, HIGH_HELIX_DEG)
    per_rad = base["right_pinion_contact_z_mm_per_horizontal_rad"]
    per_dx = base["right_pinion_contact_z_mm_per_dx_mm"]
    ok = [r for r in rows if r["status"] == "ok"]
    counts = summ["status_counts"]
    return {
        "designs": summ["designs"], "seconds": summ["seconds"],
        "ok": counts.get("ok", 0), "pointed": counts.get("pointed_teeth", 0),
        "pitch_off": counts.get("pitch_point_off_active_profile", 0), "undercut": counts.get("undercut", 0),
        "pareto": len(pareto), "pareto_small_cone": sum(d[cone] <= 0.5 for d in pareto),
        "base_fpd_deg": base["max_fpd_angle_deg"], "base_shift_mm": base["worst_path_shift_mm"],
        "base_edge_pct": 100 * base["mc_edge_fraction"],
        "alt_fpd_deg": _f(alt, "max_fpd_angle_deg"), "alt_shift_mm": _f(alt, "worst_path_shift_mm"),
        "alt_edge_pct": 100 * _f(alt, "mc_edge_fraction"),
        "lo_fpd_deg": _f(lo, "max_fpd_angle_deg"), "hi_fpd_deg": _f(hi, "max_fpd_angle_deg"),
        "lo_shift_mm": _f(lo, "worst_path_shift_mm"), "hi_shift_mm": _f(hi, "worst_path_shift_mm"),
        "lo_edge_pct": 100 * _f(lo, "mc_edge_fraction"), "hi_edge_pct": 100 * _f(hi, "mc_edge_fraction"),
        "lo_xt2": _f(lo, "gear_profile_shift"), "hi_xt2": _f(hi, "gear_profile_shift"),
        "base_te_p95_urad": base["mc_te_peak_to_peak_urad_p95"],
        "lo_te_p95_urad": _f(lo, "mc_te_peak_to_peak_urad_p95"), "hi_te_p95_urad": _f(hi, "mc_te_peak_to_peak_urad_p95"),
        "te_p95_max_urad": max(_f(r, "mc_te_peak_to_peak_urad_p95") for r in ok),
        "horizontal_mm_per_rad": per_rad, "horizontal_mm_per_deg": abs(per_rad) * math.pi / 180,
        "horizontal_share_mm": abs(per_rad) * math.radians(0.02),
        "dx_mm_per_mm": abs(per_dx), "dx_share_mm": abs(per_dx) * 0.05,
        "mc_sigma_pct": 100 * math.sqrt(0.25 / 40),
    }


#: the `beveloid paper` run whose micro-geometry study docs/input.md quotes (its loaded studies do not
#: depend on --positions: the smallest keeps the record cheap)
PAPER_ARGS = ["paper", "--positions", "20"]


def paper_numbers(folder: Path) -> dict:
    """The micro-geometry study's peak pressures at 600 N m (MPa) from a `beveloid paper` output folder:
    the unmodified pairs' (edge contact) and the tip-relieved pairs' on the study's grid (the CSV), and
    the tip-relieved peaks over every grid of the report's convergence table."""
    import re

    with open(folder / "micro_geometry_loaded.csv", newline="") as f:
        rows = [r for r in csv.DictReader(f) if float(r["pinion_torque_nm"]) == 600.0]
    peak = {(r["case"], r["flanks"]): float(r["max_pressure_mpa"]) for r in rows}
    grid = re.findall(r"^\| (case\d) \| tip relief \| (\d+x\d+) \| (\d+) \|$",
                      (folder / "report.md").read_text(encoding="utf-8"), flags=re.M)
    relieved = [float(p) for _, _, p in grid]
    return {"edge_case1_mpa": peak["case1", "unmodified"], "edge_case2_mpa": peak["case2", "unmodified"],
            "relieved_case1_mpa": peak["case1", "tip relief"], "relieved_case2_mpa": peak["case2", "tip relief"],
            "relieved_min_mpa": min(relieved), "relieved_max_mpa": max(relieved), "grids": len(grid) // 2}


def record_paper(args) -> dict:
    with tempfile.TemporaryDirectory() as tmp:
        paper_out = Path(tmp) / "paper_out"
        subprocess.run([sys.executable, "-m", "beveloid.cli", *PAPER_ARGS, "--out", str(paper_out)], cwd=ROOT,
                       check=True, stdout=subprocess.DEVNULL)
        return {"command": "beveloid " + " ".join(PAPER_ARGS) + " --out paper_out", **paper_numbers(paper_out)}


def record_explore(args) -> dict:
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "case1_explore"
        subprocess.run([sys.executable, "-m", "beveloid.cli", *EXPLORE_ARGS, "--out", str(out)], cwd=ROOT,
                       check=True, stdout=subprocess.DEVNULL)
        explore = explore_numbers(out)
        for name in ("heatmap_fpd", "heatmap_sensitivity", "pareto", "pareto_table"):  # the page's figures
            shutil.copyfile(out / f"{name}.png", ROOT / "docs" / "images" / f"explore_case1_{name}.png")
    return {"command": "beveloid " + " ".join(EXPLORE_ARGS) + " --out case1_explore", **explore}


def record_verify(args) -> dict:
    verify = json.loads(subprocess.run([sys.executable, "-m", "beveloid.cli", "verify", "--json"], cwd=ROOT,
                                       capture_output=True, text=True).stdout)
    numbered = [r for r in verify if r["equation"].isdigit()]
    return {"command": "beveloid verify --json",
            "verified": sum(r["status"] == "verified" for r in numbered),
            "definitions": sum(r["status"] == "definition" for r in numbered),
            "equations": len(numbered)}


# --- the FE groups -------------------------------------------------------------------------------

#: docs/validation.md 10: the rating's validation runs (the defaults otherwise: FE tooth), at 10 positions
#: (the rating's default was 10 when they were recorded; it is 21 since issue 57)
RATING_TORQUE_NM = 1500.0
RATING_POSITIONS = 10
RATING_COMMAND = "beveloid rating beveloid/data/{case}.toml --torque-nm 1500 --positions 10 --json"
#: the canary's coarse FE tooth: tests/fe/conftest.py's COARSEN (the session's coarse FE data)
CANARY_COARSEN = 3.0
CANARY_POSITIONS = 3


def fe_canary(analyze_ltca=None) -> dict:
    """Case 1 on the coarse FE tooth (every size x :data:`CANARY_COARSEN`): the LTCA at 9.7's torque
    and the rating at section 10's, :data:`CANARY_POSITIONS` positions each; the numbers that the FE
    tooth, the LTCA and the rating produce (see the module docstring)."""
    from beveloid import ltca, rating
    from beveloid.pair import Pair

    pair = Pair.example("case1")
    coarse = ltca.Options(positions=CANARY_POSITIONS, tooth_model="fe", fe_coarsen=CANARY_COARSEN)
    r = ltca.analyze(pair, ltca.LoadCase(500.0), coarse)
    te = (r.loaded_te - r.unloaded_te)[r.converged] * 1e6
    root = r.root_stress_max_mpa()
    rt = rating.analyze(pair, ltca.LoadCase(RATING_TORQUE_NM), rating.Options(coarse)).to_json()
    return {"ltca_loaded_te_mean_urad": float(te.mean()), "ltca_root_stress_pinion_mpa": root["pinion"],
            "ltca_root_stress_gear_mpa": root["gear"],
            **{f"rating_{m}_{k}": rt[m][k] for m in ("pinion", "gear")
               for k in ("root_stress_max_mpa", "contact_pressure_max_mpa", "safety_bending_iso", "K_H_beta")}}


def record_rating(args) -> dict:
    from beveloid import ltca, rating
    from beveloid.pair import Pair

    out = {"command": RATING_COMMAND, "canary": fe_canary()}
    for case in ("case1", "case2"):
        out[case] = rating.analyze(Pair.example(case), ltca.LoadCase(RATING_TORQUE_NM),
                                   rating.Options(ltca.Options(positions=RATING_POSITIONS))).to_json()
    return out


def record_fe_tooth(args) -> dict:
    bench_fe_tooth = _benchmark("bench_fe_tooth")

    return {"command": "python -m benchmarks.bench_fe_tooth compare", "canary": fe_canary(),
            **bench_fe_tooth.compare()}


#: the runs of docs/validation.md 11 (design, flank, torque, refinement, coarsen), in the page's order
#: docs/validation.md 11: case 1 and case 2 at the default refinement, and case 1 at refinement 2 (the
#: mesh's convergence)
FE_CHECK_RUNS = (("case1", "right", 200.0, 1, 1.0), ("case2", "right", 200.0, 1, 1.0), ("case1", "right", 200.0, 2, 1.0))


def record_fe_check(args) -> dict:
    """The runs of :data:`FE_CHECK_RUNS` from ``--fe-check-runs`` (fe_check_validation.py's JSON lines)."""
    if not args.fe_check_runs:
        raise SystemExit("--record fe_check needs --fe-check-runs RUNS.jsonl (benchmarks/fe_check_validation.py's --out)")
    rows = [json.loads(s) for s in Path(args.fe_check_runs).read_text().splitlines() if s.strip()]
    keep = []
    for design, flank, torque, refinement, coarsen in FE_CHECK_RUNS:
        found = [r for r in rows if (r["design"], r["flank"], r["torque_nm"], r["refinement"], r.get("coarsen", 1.0))
                 == (design, flank, torque, refinement, coarsen) and r.get("local_refinement") is not None]
        if not found:
            raise SystemExit(f"{args.fe_check_runs}: no run of {design}:{flank} at {torque:g} N m, refinement "
                             f"{refinement}, coarsen {coarsen:g}")
        keep.append(found[-1])
    return {"command": "python benchmarks/fe_check_validation.py (docs/validation.md 11)", "runs": keep}


def record_fe_sectors(args) -> dict:
    fe_check_sector_bcs = _benchmark("fe_check_sector_bcs")

    return {"command": "python benchmarks/fe_check_sector_bcs.py --members pinion",
            **fe_check_sector_bcs.measure(members=("pinion",))}


def fe_sectors_quotes(rec: dict) -> list:
    """docs/validation.md 11.0: the sector table as benchmarks/fe_check_sector_bcs.py prints it."""
    fe_check_sector_bcs = _benchmark("fe_check_sector_bcs")

    d = rec["fe_sectors"]["pinion"]
    outer = {name: [100 * (float(np.mean(d[name]["ratio"][i])) - 1) for i in (0, 2)] for name in d}
    lo_hi = {name: (min(abs(v) for v in vals), max(abs(v) for v in vals)) for name, vals in outer.items()}
    more = 100 * (d["7 free"]["elements"] / d["5 free"]["elements"] - 1)
    text = (f"tooth (case 1's pinion) is {lo_hi['3 free'][0]:.0f}-{lo_hi['3 free'][1]:.0f} % too compliant in a free "
            f"three-tooth sector, {lo_hi['3 clamped'][0]:.0f}-{lo_hi['3 clamped'][1]:.0f} % too stiff with the cuts",
            f"{lo_hi['5 free'][0]:.0f}-{lo_hi['5 free'][1]:.0f} % too compliant in a free five-tooth sector and\n   within "
            f"{lo_hi['7 free'][1]:.1f} % in a seven-tooth one, which costs {more:.0f} % more elements than five")
    return [("docs/validation.md", line, True) for line in fe_check_sector_bcs.table(rec["fe_sectors"])[2:]] + \
        [("docs/fe_check.md", t, True) for t in text]


def record_ltca_tables(args) -> dict:
    """docs/validation.md 7.2 and 7.5: the grid convergence and the paper's loaded study, their rows as
    the scripts print them (FE tooth; a minute or two with the FE data cached)."""
    ltca_grid_convergence, ltca_paper_loaded = _benchmark("ltca_grid_convergence"), _benchmark("ltca_paper_loaded")

    return {"command": "python benchmarks/ltca_grid_convergence.py; python benchmarks/ltca_paper_loaded.py",
            "grid_convergence": ltca_grid_convergence.rows(), "paper_loaded": ltca_paper_loaded.rows()}


def ltca_tables_quotes(rec: dict) -> list:
    t = rec["ltca_tables"]
    return [("docs/validation.md", row, True) for row in t["grid_convergence"] + t["paper_loaded"]]


GROUPS = {"explore": record_explore, "verify": record_verify, "paper": record_paper, "rating": record_rating, "fe_tooth": record_fe_tooth,
          "fe_check": record_fe_check, "fe_sectors": record_fe_sectors, "ltca_tables": record_ltca_tables}


def record(groups=tuple(GROUPS), args=None) -> dict:
    """Run the expensive sources of ``groups`` and write docs/numbers.json (the other groups kept)."""
    new = {name: GROUPS[name](args) for name in groups}
    data = recorded() if RECORD.exists() else {}  # read after the runs: another group may have been recorded
    data.update(new)
    RECORD.write_text(json.dumps(data, indent=1, allow_nan=False) + "\n")
    return data


def recorded() -> dict:
    return json.loads(RECORD.read_text())


def quotes(cheap: dict, rec: dict) -> list[tuple[str, str, bool]]:
    """(page, text it must contain, whether the number behind it holds) for every quoted number."""
    e, v, c, pp = rec["explore"], rec["verify"], cheap, rec["paper"]
    return [
        ("docs/input.md", f"the edge peaks of the unmodified pairs at 600 N m ({pp['edge_case1_mpa']:.0f} and\n"
                          f"{pp['edge_case2_mpa']:.0f} MPa, case 1 and case 2", True),
        ("docs/input.md", f"down to the surface-contact peak ({pp['relieved_case1_mpa']:.0f} and "
                          f"{pp['relieved_case2_mpa']:.0f} MPa; {pp['relieved_min_mpa']:.0f}-{pp['relieved_max_mpa']:.0f}"
                          f" MPa\nover the {pp['grids']} grids of the report's convergence table", True),

        ("docs/commands.md", f"K x N is at most {c['max_contact_points']:,} contact points", True),
        ("docs/commands.md", f"an elastic approach (default {c['approach_um']:.2f} um)", True),
        ("docs/commands.md", f"solve chunks of {c['sweep_chunk']} sets", True),
        ("docs/findings.md", f"{v['equations']} equations are accounted for: {v['verified']} derived and verified,"
                             f" {v['definitions']} are definitions", True),
        ("docs/findings.md", "two-flank backlash\n  of the Eq 27 design is below 1e-6 um",
         c["case1_backlash_um"] < 1e-6),
        ("docs/findings.md", "zero to the solver tolerance (below 1e-6 urad)", c["case1_te_ptp_urad"] < 1e-6),
        ("docs/explore.md", e["command"].replace(" --vary pinion.helix", " \\\n    --vary pinion.helix")
         .replace(" --mc 40", " \\\n    --mc 40"), True),
        ("docs/explore.md", f"{e['designs']} designs in {e['seconds']:.0f} s on this shared 2-core machine", True),
        ("docs/explore.md", f"{e['ok']} `ok`,\n{e['pointed']} `pointed_teeth`", True),
        ("docs/explore.md", f"{e['pitch_off']} `pitch_point_off_active_profile`", True),
        ("docs/explore.md", f"{e['undercut']} `undercut`", True),
        ("docs/explore.md", f"raising β1 from 12 to {HIGH_HELIX_DEG} deg", True),
        ("docs/explore.md", f"max(|ξ_L|, |ξ_R|) = {e['base_fpd_deg']:.2f} deg, a worst first-order path shift of"
                            f" {e['base_shift_mm']:.1f} mm", True),
        ("docs/explore.md", f"edge contact in {e['base_edge_pct']:.1f} % of the Monte Carlo sets", True),
        ("docs/explore.md", f"has ξ = {e['alt_fpd_deg']:.2f} deg (closer to line contact), {e['alt_shift_mm']:.1f} mm"
                            f" and {e['alt_edge_pct']:.1f} %", True),
        ("docs/explore.md", f"{e['pareto_small_cone']} of the {e['pareto']} Pareto designs", True),
        ("docs/explore.md", f"lowers ξ from {e['lo_fpd_deg']:.2f} to {e['hi_fpd_deg']:.2f} deg", True),
        ("docs/explore.md", f"raises the worst path shift from {e['lo_shift_mm']:.1f} to {e['hi_shift_mm']:.1f} mm",
         True),
        ("docs/explore.md", f"the edge-contact fraction from {e['lo_edge_pct']:.1f} % to {e['hi_edge_pct']:.1f} %",
         True),
        ("docs/explore.md", f"x_t2 = {e['lo_xt2']:.2f} at 12 deg, {e['hi_xt2']:.2f} at {HIGH_HELIX_DEG} deg", True),
        ("docs/explore.md", "the base design's is below 1e-6 µrad", e["base_te_p95_urad"] < 1e-6),
        ("docs/explore.md", "its TE peak-to-peak (95th percentile) stays below 1e-6 µrad at both ends",
         e["lo_te_p95_urad"] < 1e-6 and e["hi_te_p95_urad"] < 1e-6),
        ("docs/explore.md", f"moves {e['horizontal_mm_per_deg']:.0f} mm per degree of horizontal error", True),
        ("docs/explore.md", f"= {e['horizontal_mm_per_rad']:.0f}: {e['horizontal_share_mm']:.1f} mm of the"
                            f" {e['base_shift_mm']:.1f} mm at 0.02 deg", True),
        ("docs/explore.md", f"against {e['dx_mm_per_mm']:.1f} mm per mm of dx ({e['dx_share_mm']:.1f} mm at 0.05 mm)",
         True),
        ("docs/explore.md", f"fraction of 40 sets is ±{e['mc_sigma_pct']:.0f} %", True),
    ] + [q for group, quoted in (("fe_tooth", fe_tooth_quotes), ("rating", rating_quotes), ("fe_check", fe_check_quotes),
                                                 ("fe_sectors", fe_sectors_quotes), ("ltca_tables", ltca_tables_quotes))
         if group in rec for q in quoted(rec)]


def _pct(new, old) -> str:
    return f"{100 * (new / old - 1):+.1f} %".replace("-", "−")


def fe_tooth_quotes(rec: dict) -> list:
    """docs/loaded_contact.md 9.7: the table of ``bench_fe_tooth compare`` (FE tooth against the plate)."""
    c = rec["fe_tooth"]
    p1, f1, p2, f2 = (c[k] for k in ("case1_plate", "case1_fe", "case2_plate", "case2_fe"))

    def row(label, key, fmt, delta=True):
        cells = []
        for plate, fe in ((p1, f1), (p2, f2)):
            cells += [format(plate[key], fmt), format(fe[key], fmt) + (f" ({_pct(fe[key], plate[key])})" if delta else "")]
        return f"| {label} | " + " | ".join(cells) + " |"

    root = " | ".join(f"- | {f['root_stress_max_pinion_mpa']:.1f} / {f['root_stress_max_gear_mpa']:.1f}" for f in (f1, f2))
    hz = [f"{r[0]:.3f}-{r[1]:.3f}" for r in (p2["hertz_ratio_long_patch"], f2["hertz_ratio_long_patch"])]
    page = "docs/loaded_contact.md"
    change = {k: [100 * (f[k] / p[k] - 1) for p, f in ((p1, f1), (p2, f2))]
              for k in ("loaded_te_mean_urad", "loaded_te_ptp_urad", "mesh_stiffness_mean_n_per_um", "peak_pressure_mpa")}
    right = math.ceil(max(abs(v) for k in ("loaded_te_mean_urad", "loaded_te_ptp_urad", "peak_pressure_mpa")
                          for v in change[k]))
    share = math.ceil(100 * max(f["max_pair_share"] - p["max_pair_share"] for p, f in ((p1, f1), (p2, f2))))
    stiff, te = sorted(change["mesh_stiffness_mean_n_per_um"]), sorted(-v for v in change["loaded_te_mean_urad"])
    below = [f"{100 * (1 - r[1]):.1f}-{100 * (1 - r[0]):.1f} %" for r in (f2["hertz_ratio_long_patch"],
                                                                          p2["hertz_ratio_long_patch"])]
    text = [f"the loaded TE, its peak-to-peak and the peak pressure within {right} %; the\nload sharing within {share} "
            "points of share",
            f"is {stiff[0]:.1f}-{stiff[1]:.1f} % stiffer, so the loaded TE is {te[0]:.1f}-{te[1]:.1f} %\nlower",
            f"({below[0]} below Hertz instead of {below[1]})"]
    return [(page, t, True) for t in text] + [
            (page, row("loaded TE mean (urad)", "loaded_te_mean_urad", ".2f"), True),
            (page, row("loaded TE p-p (urad)", "loaded_te_ptp_urad", ".2f"), True),
            (page, row("mesh stiffness mean (N/um)", "mesh_stiffness_mean_n_per_um", ".1f"), True),
            (page, row("largest pair load share", "max_pair_share", ".3f", delta=False), True),
            (page, row("surface peak pressure (MPa)", "peak_pressure_mpa", ".1f"), True),
            (page, f"| root stress max pinion / gear (MPa) | {root} |", True),
            (page, f"| time of the LTCA (s, FE data cached, warm process) | {p1['seconds']:.1f} | {f1['seconds']:.1f} | "
                   f"{p2['seconds']:.1f} | {f2['seconds']:.1f} |", True),
            (page, f"peak at {hz[0]} of Hertz with the plate and at\n{hz[1]} with the FE tooth", True),
            (page, f"On case 2 the {f2['long_patches']} pairs clear of the flank edges", True)]


def _sections(m, key, fmt=".1f"):
    return " / ".join(format(m["sections"][k][key], fmt) for k in ("toe", "middle", "heel"))


RATING_HEADER = ("| case | member | ISO σ_F0 toe / middle / heel (MPa) | K_Fβ | ISO S_F (lowest) | FE root stress max "
                 "(MPa), face z, height above the root cone | local S_F | ISO σ_H0 middle (MPa) | K_Hβ | ISO S_H (lowest) | "
                 "LTCA surface peak (MPa) | local S_H | edge peak (MPa) |")


def rating_rows(rec: dict) -> list:
    """docs/validation.md 10: one table row per case and member of the recorded ratings."""
    rows = []
    for case in ("case1", "case2"):
        r = rec["rating"][case]
        for member in ("pinion", "gear"):
            m = r[member]
            loc = m["root_stress_location"]
            rows.append(
                f"| {case[-1]} | {member} | {_sections(m, 'sigma_F0_mpa')} | {m['K_F_beta']:.2f} | "
                f"{m['safety_bending_iso']:.2f} | {m['root_stress_max_mpa']:.1f}, {loc['face_z_mm']:.1f} mm, "
                f"{loc['height_above_root_mm']:.2f} mm | {m['safety_bending']:.2f} | "
                f"{m['sections']['middle']['sigma_H0_mpa']:.1f} | {m['K_H_beta']:.2f} | {m['safety_pitting_iso']:.2f} | "
                f"{m['contact_pressure_max_mpa']:.1f} | {m['safety_pitting']:.2f} | {m['edge_pressure_max_mpa']:.0f} |")
    return rows


def rating_ratio_rows(rec: dict) -> list:
    """docs/validation.md 10: the local stresses against ISO's, per case and member."""
    rows = []
    for case in ("case1", "case2"):
        for member in ("pinion", "gear"):
            m = rec["rating"][case][member]
            sec = m["sections"]
            heel = max(sec.values(), key=lambda q: q["sigma_F0_mpa"])  # ISO's largest section
            sigma_f = heel["sigma_F0_mpa"] * m["K_F_beta"]
            sigma_h = sec["middle"]["sigma_H0_mpa"] * math.sqrt(m["K_H_beta"])
            fl = m["face_load"]
            rows.append(f"| {case[-1]} | {member} | {fl['peak_line_load_n_per_mm']:.0f} / {fl['mean_line_load_n_per_mm']:.0f} "
                        f"at z = {fl['face_z_mm']:.1f} mm | {sigma_f:.1f} | {m['root_stress_max_mpa'] / sigma_f:.2f} | "
                        f"{sigma_h:.1f} | {m['contact_pressure_max_mpa'] / sigma_h:.2f} |")
    return rows


def rating_quotes(rec: dict) -> list:
    page = "docs/validation.md"
    out = [(page, row, True) for row in [RATING_HEADER] + rating_rows(rec) + rating_ratio_rows(rec)]
    for case in ("case1", "case2"):
        v = rec["rating"][case]["verdict"]
        out.append((page, f"verdict: {v['line']}", True))
    return out


def fe_check_ratio_rows(rec: dict) -> list:
    """docs/validation.md 11.1: per run, FE / LTCA of the pair loads, the TE's lag and the root stresses."""
    rows = []
    for r in rec["fe_check"]["runs"]:
        c, lt = r["calculix"], r["ltca"]
        loads = "; ".join(f"{a / b:.2f}" for a, b in zip(c["pair_normal_load_n"], lt["pair_normal_load_n"]) if a and b)
        u = r["unloaded_transmission_error_urad"]
        lag = (c["loaded_transmission_error_urad"] - u) / (lt["loaded_transmission_error_urad"] - u)
        root = " / ".join(f"{c['root_stress_max_mpa'][m] / lt['root_stress_max_mpa'][m]:.2f}" for m in ("pinion", "gear"))
        rows.append(f"| {r['design']} {r['flank']}, {r['torque_nm']:g} N m, refinement {r['refinement']} | {loads} | "
                    f"{lag:.3f} | {root} |")
    return rows


def fe_check_quotes(rec: dict) -> list:
    """docs/validation.md 11: the validation tables as benchmarks/fe_check_validation.py prints them."""
    v = _benchmark("fe_check_validation")

    runs = rec["fe_check"]["runs"]
    lines = v.table(runs).splitlines()[2:] + v.hertz_table(runs).splitlines()[2:] + fe_check_ratio_rows(rec)
    r = runs[0]  # case 1 at refinement 1: the default run's cost in docs/fe_check.md
    cost = (f"case 1 at {r['torque_nm']:g} N m: {_spaced(r['elements'])} elements, {_spaced(r['dof'])} DOF, CalculiX\n  "
            f"{r['calculix_cpu_s']:.0f} s of CPU (2 threads); on this shared 2-core machine, beside other work,\n  "
            f"the whole run (LTCA, meshing, CalculiX) took {r['total_s']:.0f} s of wall time")
    return [("docs/validation.md", line, True) for line in lines] + [("docs/fe_check.md", cost, True)] + \
        [("docs/performance.md", row, True) for row in fe_check_cost_rows(rec)]


def _spaced(n: int) -> str:
    return f"{n:,}".replace(",", " ")


def fe_check_cost_rows(rec: dict) -> list:
    """docs/performance.md, the fe-check section: each recorded run's size and times."""
    return [f"| {r['design'].replace('case', 'case ')} {r['flank']}, {r['torque_nm']:g} N m, refinement {r['refinement']} | "
            f"{_spaced(r['elements'])} | {_spaced(r['dof'])} | {r['mesh_s']:.0f} | {r['calculix_wall_s']:.0f} / "
            f"{r['calculix_cpu_s']:.0f} | {r['total_s']:.0f} |" for r in rec["fe_check"]["runs"]]


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--record", nargs="?", const=",".join(GROUPS), default=None, metavar="GROUPS",
                   help=f"rerun the expensive sources into docs/numbers.json: all, or these ({', '.join(GROUPS)})")
    p.add_argument("--fe-check-runs", default=None, help="fe_check_validation.py's runs file (--record fe_check)")
    p.add_argument("--print", action="store_true", help="print every quote as it should read")
    args = p.parse_args(argv)
    sys.path.insert(0, str(ROOT))
    groups = [] if args.record is None else args.record.split(",")
    unknown = [g for g in groups if g not in GROUPS]
    if unknown:
        p.error(f"--record = {args.record!r}: unknown group {unknown[0]!r}; valid: {', '.join(GROUPS)}")
    rec = record(groups, args) if groups else recorded()
    bad = 0
    for page, text, holds in quotes(cheap_numbers(), rec):
        found = text in (ROOT / page).read_text(encoding="utf-8")
        if args.print or not (found and holds):
            print(f"{page}: {'ok' if found and holds else 'MISSING' if not found else 'NO LONGER HOLDS'}: {text!r}")
        bad += not (found and holds)
    return 1 if bad else 0


if __name__ == "__main__":
    raise SystemExit(main())

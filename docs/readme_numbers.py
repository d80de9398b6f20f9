"""The numbers the README and the docs pages quote, and where each is quoted.

    python docs/readme_numbers.py             # check: every quote below is in its page (exit 1 if not)
    python docs/readme_numbers.py --print     # the quotes as they should read now
    python docs/readme_numbers.py --record    # rerun the expensive sources, rewrite docs/numbers.json

Two kinds of numbers:

* cheap ones, computed here each time (constants of the package, one TCA of case 1: ~1 s);
* expensive ones, recorded in ``docs/numbers.json`` by ``--record``, which runs the commands named
  there (the worked exploration of docs/explore.md: 216 designs with a Monte Carlo sweep each;
  ``beveloid verify --json``; ``beveloid paper`` for the micro-geometry study's pressures), and copies the exploration's figures into docs/images/.  A page quoting them must match the JSON; after a change that moves
  them, rerun ``--record`` and paste what ``--print`` shows.

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


def record() -> dict:
    """Run the expensive sources and write docs/numbers.json."""
    with tempfile.TemporaryDirectory() as tmp:
        paper_out = Path(tmp) / "paper_out"
        subprocess.run([sys.executable, "-m", "beveloid.cli", *PAPER_ARGS, "--out", str(paper_out)], cwd=ROOT,
                       check=True, stdout=subprocess.DEVNULL)
        paper = paper_numbers(paper_out)
        out = Path(tmp) / "case1_explore"
        subprocess.run([sys.executable, "-m", "beveloid.cli", *EXPLORE_ARGS, "--out", str(out)], cwd=ROOT,
                       check=True, stdout=subprocess.DEVNULL)
        explore = explore_numbers(out)
        for name in ("heatmap_fpd", "heatmap_sensitivity", "pareto", "pareto_table"):  # the page's figures
            shutil.copyfile(out / f"{name}.png", ROOT / "docs" / "images" / f"explore_case1_{name}.png")
    verify = json.loads(subprocess.run([sys.executable, "-m", "beveloid.cli", "verify", "--json"], cwd=ROOT,
                                       capture_output=True, text=True).stdout)
    numbered = [r for r in verify if r["equation"].isdigit()]
    data = {
        "explore": {"command": "beveloid " + " ".join(EXPLORE_ARGS) + " --out case1_explore", **explore},
        "paper": {"command": "beveloid " + " ".join(PAPER_ARGS) + " --out paper_out", **paper},
        "verify": {"command": "beveloid verify --json",
                   "verified": sum(r["status"] == "verified" for r in numbered),
                   "definitions": sum(r["status"] == "definition" for r in numbered),
                   "equations": len(numbered)},
    }
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
    ]


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--record", action="store_true", help="rerun the expensive sources into docs/numbers.json")
    p.add_argument("--print", action="store_true", help="print every quote as it should read")
    args = p.parse_args(argv)
    sys.path.insert(0, str(ROOT))
    rec = record() if args.record else recorded()
    bad = 0
    for page, text, holds in quotes(cheap_numbers(), rec):
        found = text in (ROOT / page).read_text(encoding="utf-8")
        if args.print or not (found and holds):
            print(f"{page}: {'ok' if found and holds else 'MISSING' if not found else 'NO LONGER HOLDS'}: {text!r}")
        bad += not (found and holds)
    return 1 if bad else 0


if __name__ == "__main__":
    raise SystemExit(main())

"""The edge rule's measure against the contact grid: the share of the mesh's load within 0.05 m_n of a flank edge.

For design K of ``benchmarks/rating_invariance.py`` (an uncrowned gear whose ends the line contact reaches) at 130
and 300 N m, case 1 at 300 and 1500 N m (the loaded pattern runs onto both tips), both on the FE tooth (the
rating's default), and the 19/43 pair of issue 60 (``tests/data/issue60_pair.toml``) at 125 N m with its
pinion's tip unrelieved and with 10 and 18 um of tip relief (1.2 mm long) on the plate tooth, and K on the plate
tooth too: the LTCA at the rating's load (K_A K_v T) and 21 positions on the grids 7x11 / 11x17 / 15x25 / 21x33,
and each edge's largest share over the positions (``rating.edge.edge_loads``, by edge, over the rule's 2 % or
the most loaded; "-" where no loaded cell comes near it) with each cell's force spread over its footprint on the flank uniformly (the verdict's) and
weighted by the distance to the edge to the power -1/2 (``profile="punch"``, the pressure's form near a sharp
punch corner; docs/rating.md 6).

    python benchmarks/edge_band_convergence.py [--cases K,case1,relief,Kplate]
"""
from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

GRIDS = ((7, 11), (11, 17), (15, 25), (21, 33))
ROOT = Path(__file__).resolve().parents[1]


def _cases(keys):
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from rating_invariance import DESIGNS

    from beveloid.pair import Pair
    from beveloid.spec import spec_from_toml_bytes

    def from_text(text):
        return Pair.from_spec(spec_from_toml_bytes(text.encode()))

    design_k = from_text(DESIGNS[next(n for n in DESIGNS if n.startswith("K "))])
    out = []
    if "K" in keys:
        out += [("K", design_k, t, "fe") for t in (130.0, 300.0)]
    if "case1" in keys:
        out += [("case 1", Pair.example("case1"), t, "fe") for t in (300.0, 1500.0)]
    if "relief" in keys:
        text = (ROOT / "tests" / "data" / "issue60_pair.toml").read_text(encoding="utf-8")
        for relief in (0.0, 10.0, 18.0):
            t = text if not relief else re.sub(r"\[gear\]", f"tip_relief_um = {relief:g}\ntip_relief_height_mm = 1.2\n"
                                               "[gear]", text, count=1)
            out.append((f"19/43, pinion tip relief {relief:g} um", from_text(t), 125.0, "plate"))
    if "Kplate" in keys:
        out += [("K", design_k, t, "plate") for t in (130.0, 300.0)]
    return out


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--cases", default="K,case1,relief,Kplate",
                   help="comma-separated: K, case1, relief, Kplate (all by default)")
    args = p.parse_args(argv)
    keys = {k.strip() for k in args.cases.split(",") if k.strip()}
    if not keys or keys - {"K", "case1", "relief", "Kplate"}:
        p.error(f"--cases = {args.cases!r}: valid are K, case1, relief, Kplate (comma-separated)")

    from beveloid import ltca, rating
    from beveloid.rating.edge import edge_loads
    from beveloid.rating.verdict import EDGE_SHARE

    print("| design | T (N m) | tooth | edge | spread | " + " | ".join(f"{a}x{b}" for a, b in GRIDS) + " |")
    print("|---|---|---|---|---|" + "---|" * len(GRIDS))
    for name, pair, torque, tooth in _cases(keys):
        # the rating's load on the LTCA: K_A K_v T (K_v by method B from a first rating where the spec has a speed)
        f = rating.analyze(pair, ltca.LoadCase(torque), rating.Options(ltca=ltca.Options(tooth_model=tooth))).factors
        shares = {}  # (edge, spread) -> one share per grid
        for i, grid in enumerate(GRIDS):
            r = ltca.analyze(pair, ltca.LoadCase(torque * f.K_A * f.K_v),
                             ltca.Options(positions=rating.Options().ltca.positions, grid=grid, tooth_model=tooth))
            for profile in ("uniform", "punch"):
                for e in edge_loads(r, pair.geometry, by_edge=True, profile=profile):
                    shares.setdefault((f"{e.member} {e.edge}", profile), [None] * len(GRIDS))[i] = e.share
        peak = {key: max(v or 0.0 for v in values) for key, values in shares.items()}
        # each edge over a quarter of the rule's limit on some grid, and the most loaded edge of each spread
        show = {edge for (edge, _), v in peak.items() if v >= EDGE_SHARE / 4}
        show |= {max((key for key in peak if key[1] == s), key=peak.get)[0] for s in ("uniform", "punch")
                 if any(key[1] == s for key in peak)}
        for edge in sorted(show):
            for profile in ("uniform", "punch"):
                values = shares.get((edge, profile), [None] * len(GRIDS))
                print(f"| {name} | {torque:g} | {tooth} | {edge} | {profile} | "
                      + " | ".join("-" if v is None else f"{v:.4f}" for v in values) + " |", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

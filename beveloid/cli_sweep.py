"""``beveloid sweep FILE --samples K --positions N [--seed S] [--flank left|right] [--json]``."""
from __future__ import annotations

import argparse
import json
import sys

from .errors import UserError
from .sweep import DEFAULT_RANGES


def configure(p: argparse.ArgumentParser) -> None:
    p.add_argument("file", metavar="FILE", help="TOML design spec (see examples/case1.toml)")
    p.add_argument("--samples", type=int, default=1000, metavar="K", help="random error sets (default 1000)")
    p.add_argument("--positions", type=int, default=50, metavar="N",
                   help="contact positions per set over the aligned engagement (default 50)")
    p.add_argument("--seed", type=int, default=0, metavar="S", help="random seed (default 0)")
    p.add_argument("--flank", choices=("left", "right"), default="right", help="flank pair (default right)")
    for key, val in DEFAULT_RANGES.items():
        unit = "MM" if key.endswith("_mm") else "DEG"
        p.add_argument("--" + key.replace("_mm", "").replace("_deg", "") + "-max", dest=key, type=float,
                       default=val, metavar=unit, help=f"half-width of the uniform {key} range (default {val})")
    p.add_argument("--backend", choices=("auto", "compiled", "numpy"), default="auto",
                   help="solver backend: compiled (numba) when installed, else numpy (default auto)")
    p.add_argument("--json", action="store_true", help="print the result as JSON on stdout")


def run(args: argparse.Namespace) -> int:
    """Monte Carlo tolerance sweep over random assembly errors.

    Reports the contact-path shift distribution, the fraction of error sets with edge contact
    or contact off the flank, TE peak-to-peak statistics and first-order sensitivities.
    """
    from . import tca
    from .design import design
    from .spec import load_spec
    from .sweep import _progress_bar, sweep

    if not 1 <= args.samples <= 10_000_000:
        raise UserError(f"--samples = {args.samples}: must be an integer from 1 to 10000000")
    if not 0 <= args.seed < 2 ** 63:
        raise UserError(f"--seed = {args.seed}: must be an integer from 0 to 2**63 - 1")
    if not 2 <= args.positions <= 10_000:
        raise UserError(f"--positions = {args.positions}: must be an integer from 2 to 10000")
    ranges = {}
    for key in DEFAULT_RANGES:
        v = getattr(args, key)
        if not (v >= 0 and v < (10 if key.endswith("_mm") else 5)):
            name = "--" + key.replace("_mm", "").replace("_deg", "") + "-max"
            raise UserError(f"{name} = {v}: must be >= 0 and < {10 if key.endswith('_mm') else 5} "
                            f"({'mm' if key.endswith('_mm') else 'deg'})")
        ranges[key] = v
    geom = tca.PairGeometry.from_design(design(load_spec(args.file)))
    progress = _progress_bar if sys.stderr.isatty() else None
    res = sweep(geom, args.flank, args.samples, args.positions, args.seed, ranges, args.backend, progress=progress)
    out = res.to_json_dict()
    if args.json:
        print(json.dumps(out, allow_nan=False))
        return 0
    print(format_sweep(out, args.file))
    return 0


def _row(name, st, unit, scale=1.0, fmt="{:+.3f}"):
    if not st.get("count"):
        return f"  {name:<28} (no set with contact on the flank)"
    vals = [fmt.format(st[k] * scale) for k in ("mean", "std", "p05", "p50", "p95")]
    return f"  {name:<28} " + "  ".join(f"{v:>10}" for v in vals) + f"  {unit}"


def format_sweep(o, file):
    L = [f"Tolerance sweep of {file}, {o['flank']} flank: {o['samples']} error sets x {o['positions']} positions "
         f"= {o['contact_points_solved']} contact points ({o['backend']}, {o['seconds']:.2f} s, "
         f"{o['us_per_point']:.2f} us/point)",
         "  error ranges (uniform, +-): " + ", ".join(f"{k} {v:g}" for k, v in o["ranges"].items()), "",
         f"  {'':<28} " + "  ".join(f"{h:>10}" for h in ("mean", "std", "p5", "p50", "p95")),
         _row("pinion path shift", o["pinion_path_shift_mm"], "mm"),
         _row("gear path shift", o["gear_path_shift_mm"], "mm"),
         _row("TE peak-to-peak", o["te_peak_to_peak_urad"], "urad", fmt="{:.2e}"), "",
         f"  sets with edge contact:           {100 * o['fraction_sets_with_edge_contact']:.1f} %",
         f"  sets with contact off the flank:  {100 * o['fraction_sets_with_contact_off_flank']:.1f} %",
         f"  sets entirely off the flank:      {100 * o['fraction_sets_entirely_off_flank']:.1f} %", "",
         "  first-order sensitivity of the path (pinion axial shift):"]
    for k, v in o["sensitivity"]["pinion_axial_shift_mm_per_unit"].items():
        unit = "mm/mm" if k.endswith("_mm") else "mm/deg"
        L.append(f"    {k:<16} {v:+10.3f} {unit}")
    return "\n".join(L)

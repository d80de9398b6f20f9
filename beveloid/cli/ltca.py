"""``beveloid ltca FILE --torque-nm T [--positions N] [--pairs K] [--flank left|right] [--dx MM] [--dy MM]
[--dz MM] [--vertical DEG] [--horizontal DEG] [--grid ACROSSxALONG] [--plot OUT.png] [--json]``.

Loaded tooth contact analysis (approximate: half-space + thin-slice teeth, frictionless; see
docs/loaded_contact.md).  The torque is the pinion torque.  The JSON holds "torque_nm",
"pinion_angle_rad" [N], "loaded_transmission_error_urad" [N], "tooth_pairs" [P],
"pair_normal_load_n" [N][P], "pair_max_pressure_mpa" [N][P], "pair_patch_semi_axes_mm" [N][P][2]
(across, along: sqrt(5 <x^2>) of the pressure), "contact_area_mm2" [N],
"pattern_area_fraction" {"pinion", "gear"}, "status" [N] and "solver" (iterations and residuals);
a position that did not converge has null numbers.
"""
from __future__ import annotations

import argparse
import json
import math
import re

from .paths import check_output_file
from .common import add_error_flags, apply_error_flags, error_vector, errors_label
from ..errors import UserError


def configure(p: argparse.ArgumentParser) -> None:
    p.add_argument("file", metavar="FILE", help="TOML design spec (`beveloid example case1` prints one)")
    p.add_argument("--torque-nm", type=float, required=True, metavar="T", help="pinion torque (N m), > 0")
    p.add_argument("--positions", type=int, default=20, metavar="N",
                   help="pinion positions over one mesh cycle (default 20)")
    p.add_argument("--pairs", type=int, default=3, metavar="K", help="neighbouring tooth pairs (default 3)")
    p.add_argument("--flank", choices=("left", "right"), default="right", help="flank pair (default right)")
    add_error_flags(p)
    p.add_argument("--grid", default="13x31", metavar="ACROSSxALONG",
                   help="contact cells across x along the contact line per tooth pair (default 13x31)")
    p.add_argument("--plot", metavar="OUT.png", help="write the contact patterns, loaded TE and load sharing here")
    p.add_argument("--json", action="store_true", help="print the result as JSON on stdout")


def parse_grid(text: str):
    m = re.fullmatch(r"\s*(\d+)\s*[xX]\s*(\d+)\s*", text or "")
    if not m or not (3 <= int(m[1]) <= 201 and 3 <= int(m[2]) <= 201):
        raise UserError(f"--grid = {text}: must be ACROSSxALONG with two integers from 3 to 201, e.g. 13x31")
    return int(m[1]), int(m[2])


def run(args: argparse.Namespace) -> int:
    """Loaded tooth contact analysis under a pinion torque (approximate: half-space + tooth beams).

    Prints per position the loaded TE, the load of each tooth pair, its peak pressure and the
    contact area; --json prints the full arrays.
    """
    from .. import ltca, tca
    from ..design import design
    from ..spec import load_spec

    t = args.torque_nm
    if not (math.isfinite(t) and 0 < t <= 1e6):
        raise UserError(f"--torque-nm = {t}: must be a number > 0 and <= 1000000 (N m)")
    if args.positions < 3 or args.positions > 400:
        raise UserError(f"--positions = {args.positions}: must be an integer from 3 to 400")
    if args.pairs < 1 or args.pairs > 9 or args.pairs % 2 == 0:
        raise UserError(f"--pairs = {args.pairs}: must be an odd integer from 1 to 9")
    across, along = parse_grid(args.grid)
    if args.plot is not None:
        check_output_file(args.plot, "--plot", ".png")
    spec = apply_error_flags(load_spec(args.file), args)
    geom = tca.PairGeometry.from_design(design(spec))
    result = ltca.analyze(geom, t, flank=args.flank, errors=error_vector(spec), positions=args.positions,
                          pairs=args.pairs, grid=ltca.GridOptions(across_cells=across, along_cells=along),
                          material=ltca.Material.from_spec(spec))
    if args.plot is not None:
        from ..plots import ltca_summary

        try:
            ltca_summary(result, geom, args.plot, title=f"{spec.source}: pinion torque {t:g} N m, {errors_label(spec)}")
        except OSError as exc:
            raise UserError(f"--plot = {args.plot}: cannot write there ({exc.strerror or exc})") from None
    if args.json:
        print(json.dumps(result.to_json_dict(geom), allow_nan=False))
    else:
        print(format_summary(result, geom, spec))
    return 0


def format_summary(result, geom, spec) -> str:
    fmt = lambda v, f: "-" if v is None or not math.isfinite(v) else format(v, f)  # noqa: E731
    lines = [f"Loaded TCA of {spec.source}, {result.flank} flank, pinion torque {result.torque_nm:g} N m,"
             f" {errors_label(spec)}", ""]
    head = ["phi1 (mrad)", "status", "TE loaded (urad)", "TE unloaded (urad)", "area (mm2)"]
    head += [f"F pair {k} (N)" for k in result.tooth_pairs] + [f"p_max pair {k} (MPa)" for k in result.tooth_pairs]
    rows = [head]
    for j, phi in enumerate(result.pinion_angle):
        rows.append([f"{phi * 1e3:.3f}", result.status[j], fmt(result.loaded_te[j] * 1e6, ".3f"),
                     fmt(result.unloaded_te[j] * 1e6, ".3f"), fmt(result.contact_area_mm2[j], ".2f")]
                    + [fmt(v, ".1f") for v in result.pair_load_n[j]]
                    + [fmt(v, ".0f") for v in result.pair_max_pressure_mpa[j]])
    w = [max(len(r[i]) for r in rows) for i in range(len(head))]
    lines += ["  ".join(c.rjust(wi) for c, wi in zip(r, w)) for r in rows]
    frac = {m: result.pattern(geom, m).area_fraction for m in ("pinion", "gear")}
    lines += ["", "share of each flank that carries pressure somewhere in the cycle: "
              + ", ".join(f"{m} {fmt(f * 100 if f is not None else None, '.1f')}%" for m, f in frac.items()),
              f"grid per pair: {result.grid.across_cells} x {result.grid.along_cells} cells over "
              f"+-{result.across_half_mm:.3f} mm across and +-{result.along_half_mm:.2f} mm along the contact line"]
    lines += [f"note: {n}" for n in result.notes]
    lines += ["approximate: Boussinesq half-space + thin-slice tooth beams, frictionless (docs/loaded_contact.md)"]
    return "\n".join(lines)

"""``beveloid ltca FILE --torque-nm T [--positions N] [--pairs K] [--flank left|right] [--dx MM] [--dy MM]
[--dz MM] [--vertical DEG] [--horizontal DEG] [--grid ACROSSxALONG] [--plot OUT.png] [--json]``.

Loaded tooth contact analysis (approximate: half-space + thin-slice teeth, frictionless; see
docs/loaded_contact.md).  The torque is the pinion torque.  The JSON holds "torque_nm",
"pinion_angle_rad" [N], "loaded_transmission_error_urad" [N], "tooth_pairs" [P],
"pair_normal_load_n" [N][P], "pair_max_pressure_mpa" [N][P], "pair_patch_semi_axes_mm" [N][P][2]
(across, along: sqrt(5 <x^2>) of the pressure), "contact_area_mm2" [N],
"pattern_area_fraction" {"pinion", "gear"}, "status" [N] and "solver" (iterations and residuals);
a position that did not converge has null numbers.  Since issue 23 also: "pair_surface_max_pressure_mpa"
and "pair_edge_max_pressure_mpa" [N][P] (the peak away from / at a flank edge; the edge one is
grid-dependent), "grid_convergence" (per position the change of the surface peak and of the pair
loads against the once-coarsened grid, with tolerances), "validity" (None per position inside the
model: linear elastic, small strain), "loaded_transmission_error_peak_to_peak_urad" (null with fewer
than 3 converged positions), "warnings" (also printed on stderr), per-pair grid extents,
"pair_hertz_max_pressure_mpa" [N][P] with its note, and "tooth_height_mm" {"pinion", "gear"}
(the Hertz note's yardstick: the LTCA holds Hertz within 5 % where the patch's semi-axis along
the contact is under half of it).
"""
from __future__ import annotations

import argparse
import json
import math
import re

from .paths import check_output_file
from .common import add_error_flags, apply_error_flags, error_vector, errors_label, number
from ..errors import OptionError, UserError


def configure(p: argparse.ArgumentParser) -> None:
    p.add_argument("file", metavar="FILE", help="TOML design spec (`beveloid example case1` prints one)")
    p.add_argument("--torque-nm", type=float, required=True, metavar="T", help="pinion torque (N m), > 0")
    p.add_argument("--positions", type=int, default=20, metavar="N",
                   help="pinion positions over one mesh cycle (default 20)")
    p.add_argument("--pairs", type=int, default=3, metavar="K", help="neighbouring tooth pairs (default 3)")
    p.add_argument("--flank", choices=("left", "right"), default="right", help="flank pair (default right)")
    add_error_flags(p)
    p.add_argument("--grid", default=None, metavar="ACROSSxALONG",
                   help="contact cells across x along the contact line per tooth pair (default "
                        "11x17, each cell a fixed fraction of the pair's Hertz semi-axes)")
    p.add_argument("--tooth-model", choices=("fe", "plate"), default=None,
                   help="how the teeth bend: fe = finite-element tooth from the real geometry with root stress "
                        "(default; its data is cached per design), plate = the fast equivalent-spur-tooth plate")
    p.add_argument("--fe-refinement", type=int, default=1, metavar="N",
                   help="FE tooth mesh refinement, 1-4 (default 1; 2 halves every element size)")
    p.add_argument("--fe-coarsen", type=float, default=1.0, metavar="F",
                   help="every FE tooth element size times F, 1-8 (default 1; 2-4: a quick, rougher tooth)")
    p.add_argument("--plot", metavar="OUT.png", help="write the contact patterns, loaded TE and load sharing here "
                                                     "(and the per-position pressure maps beside it)")
    p.add_argument("--json", action="store_true", help="print the result as JSON on stdout")


def parse_grid(text):
    """(across, along) from 'AxB', None when not given; the range is ltca.options' (one line if bad)."""
    from ..ltca.options import check_grid

    if text is None:
        return None
    m = re.fullmatch(r"\s*(\d+)\s*[xX]\s*(\d+)\s*", text)
    try:
        return check_grid((int(m[1]), int(m[2])) if m else text, key="--grid")
    except OptionError as exc:  # named by its fields: the flag and the text as typed
        raise UserError(exc.for_flag("--grid", shown=text)) from None


def run(args: argparse.Namespace) -> int:
    """Loaded tooth contact analysis under a pinion torque (approximate: half-space + tooth beams).

    Prints per position the loaded TE, the load of each tooth pair, its peak pressure and the
    contact area; --json prints the full arrays.  Warnings (grid not converged, outside the
    model's validity, edge peaks) go to stderr, one line each.
    """
    import sys

    from .. import ltca
    from ..pair import Pair
    from ..solver import Solver

    grid = parse_grid(args.grid)
    try:
        ltca.options.check_torque(args.torque_nm, key="--torque-nm")
        ltca.options.check_positions(args.positions, key="--positions")
        ltca.options.check_pairs(args.pairs, key="--pairs")
        ltca.options.check_fe_refinement(args.fe_refinement, key="--fe-refinement")
        ltca.options.check_fe_coarsen(args.fe_coarsen, key="--fe-coarsen")
    except OptionError as exc:
        raise UserError(exc.for_flag(exc.key)) from None
    if args.plot is not None:
        check_output_file(args.plot, "--plot", ".png")
    from ..spec import load_spec

    spec = apply_error_flags(load_spec(args.file), args)
    pair = Pair.from_spec(spec)
    options = ltca.Options(torque_nm=args.torque_nm, flank=args.flank, positions=args.positions, pairs=args.pairs,
                           grid=grid, errors=tuple(error_vector(spec)), material=ltca.Material.from_spec(spec),
                           tooth_model=args.tooth_model, fe_refinement=args.fe_refinement,
                           fe_coarsen=args.fe_coarsen)
    try:
        options.check_memory()
    except OptionError as exc:
        raise UserError(exc.for_flag("--grid")) from None
    result = ltca.analyze(pair, options, Solver())
    geom = pair.geometry
    if args.plot is not None:
        from ..ltca.plots import ltca_summary

        try:
            ltca_summary(result, geom, args.plot, title=f"{spec.source}: pinion torque {args.torque_nm:g} N m, "
                                                        f"{errors_label(spec)}")
        except OSError as exc:
            raise UserError(f"--plot = {args.plot}: cannot write there ({exc.strerror or exc})") from None
    for w in result.warnings():
        print(f"beveloid: warning: {w}", file=sys.stderr)
    if args.json:
        print(json.dumps(ltca.to_json_dict(result, geom), allow_nan=False))
    else:
        print(format_summary(result, geom, spec))
    return 0


def _root_stress_lines(result) -> list:
    if result.tooth_model != "fe":
        return ["root stress: not computed with the plate tooth (--tooth-model fe)"]
    top, where = result.root_stress_max_mpa(), result.root_stress_location()
    out = []
    for m in ("pinion", "gear"):
        if top.get(m) is None:
            out.append(f"{m} root stress: not available (no converged position)")
            continue
        w = where[m]
        out.append(f"{m} root stress (max principal, loaded fillet): {top[m]:.1f} MPa at position {w['position']}, "
                   f"pair {w['pair']}, z = {w['z_mm']:.2f} mm, {w['height_mm']:.2f} mm above the root")
    return out


def format_summary(result, geom, spec) -> str:
    fmt = number
    lines = [f"Loaded TCA of {spec.source}, {result.flank} flank, pinion torque {result.torque_nm:g} N m,"
             f" {errors_label(spec)}", ""]
    head = ["phi1 (mrad)", "status", "TE loaded (urad)", "TE unloaded (urad)", "area (mm2)"]
    head += [f"F pair {k} (N)" for k in result.tooth_pairs] + [f"p_max pair {k} (MPa)" for k in result.tooth_pairs]
    rows = [head]
    for j, phi in enumerate(result.pinion_angle):
        rows.append([f"{phi * 1e3:.3f}", result.status[j], fmt(result.loaded_te[j] * 1e6, ".3f"),
                     fmt(result.unloaded_te[j] * 1e6, ".3f"), fmt(result.contact_area_mm2[j], ".2f")]
                    + [fmt(v, ".1f") for v in result.pair_load_n[j]]
                    + [fmt(v, ".0f") + ("*" if math.isfinite(e) and e >= v else "")
                       for v, e in zip(result.pair_max_pressure_mpa[j], result.pair_edge_max_pressure_mpa[j])])
    w = [max(len(r[i]) for r in rows) for i in range(len(head))]
    lines += ["  ".join(c.rjust(wi) for c, wi in zip(r, w)) for r in rows]
    frac = {m: result.pattern(geom, m).area_fraction for m in ("pinion", "gear")}
    lines += ["", "share of each flank that carries pressure somewhere in the cycle: "
              + ", ".join(f"{m} {fmt(f * 100 if f is not None else None, '.1f')}%" for m, f in frac.items()),
              f"grid per pair: {result.grid.across_cells} x {result.grid.along_cells} cells, sized from each pair's Hertz "
              f"semi-axes (up to +-{result.across_half_mm:.3f} mm across and +-{result.along_half_mm:.2f} mm along the"
              " contact line)"]
    if any("*" in c for r in rows[1:] for c in r):
        lines += ["* the peak is at a flank edge: grid-dependent (see pair_edge_max_pressure_mpa and "
                  "pair_surface_max_pressure_mpa in --json)"]
    ptp = result.loaded_te_peak_to_peak
    lines += [f"loaded TE peak-to-peak: {fmt(ptp * 1e6, '.3f')} urad" if math.isfinite(ptp) else
              "loaded TE peak-to-peak: not available (needs 3 or more converged positions)"]
    lines += _root_stress_lines(result)
    lines += [f"note: {n}" for n in result.notes]
    teeth = (f"FE tooth (refinement {result.fe_refinement})" if result.tooth_model == "fe"
             else "thin-slice plate tooth beams")
    lines += [f"approximate: Boussinesq half-space + {teeth}, frictionless (docs/loaded_contact.md)"]
    return "\n".join(lines)

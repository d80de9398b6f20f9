"""``beveloid tca FILE [--dx MM] [--dy MM] [--dz MM] [--vertical DEG] [--horizontal DEG]
[--flank left|right|both] [--positions N] [--approach-um UM] [--plot OUT.png] [--json]``.

Flags override the file's [misalignment] table.  The JSON holds "flanks" (keyed "left" and/or
"right", each with equal-length arrays, Newton iterations per point and their mean),
"te_peak_to_peak_urad" and "newton_iterations_mean" per flank and, when both flanks are solved,
"backlash_um" with "backlash_status": the smallest circumferential play over a mesh cycle at the
gear's working pitch circle, positive = play, negative = the flanks interfere, with
"backlash_at_reference_um" and "backlash_max_um"; numbers only when the status is "ok" (both
flanks touch on their flanks somewhere in the cycle), else null with the status of the missing
contact ("outside" or "failed") and a note saying why.  The contact ellipses per flank
("contact_ellipse_*", beveloid/contact_ellipse.py) and "approach_mm".
"""
from __future__ import annotations

import argparse
import json

import numpy as np

from .common import add_error_flags, apply_error_flags, errors_label, number
from .paths import check_output_file
from ..errors import UserError
from ..status import PointStatus


def configure(p: argparse.ArgumentParser) -> None:
    p.add_argument("file", metavar="FILE", help="TOML design spec (`beveloid example case1` prints one)")
    add_error_flags(p)
    p.add_argument("--flank", choices=("left", "right", "both"), default="both", help="flank pair (default both)")
    p.add_argument("--positions", type=int, default=200, metavar="N",
                   help="pinion positions over the mesh window (default 200)")
    p.add_argument("--pairs", type=int, default=3, metavar="K", help="neighbouring tooth pairs (default 3)")
    p.add_argument("--plot", metavar="OUT.png", help="write contact paths and TE to this PNG")
    p.add_argument("--approach-um", type=float, default=6.32, metavar="UM",
                   help="elastic approach of the contact ellipses (um, default 6.32, the paint-layer value)")
    p.add_argument("--json", action="store_true", help="print the result as JSON on stdout")


def run(args: argparse.Namespace) -> int:
    """Tooth contact analysis under the five assembly errors (Eqs 28-38).

    Prints per flank the contact statuses, the path's place on the flanks, the TE
    peak-to-peak and the backlash; --json prints the full arrays.
    """
    from .. import tca
    from ..contact_ellipse import check_approach
    from ..pair import Pair
    from ..spec import load_spec

    approach_mm = check_approach(args.approach_um * 1e-3, "--approach-um", 1e3, "um")  # one line naming the flag
    try:
        options = tca.Options(flanks=tca.FLANKS if args.flank == "both" else (args.flank,),
                              positions=args.positions, pairs=args.pairs, approach_mm=approach_mm)
    except tca.OptionError as exc:
        raise UserError(exc.for_flag("--" + exc.key.replace("_", "-"))) from None
    if args.plot is not None:
        check_output_file(args.plot, "--plot", ".png")
    spec = apply_error_flags(load_spec(args.file), args)
    pair = Pair.from_spec(spec)
    geom = pair.geometry
    result = tca.analyze(pair, options, solver=tca.Solver())
    if args.plot is not None:
        from ..plots import tca_summary

        try:
            tca_summary(result, geom, args.plot, title=f"{spec.source}: {errors_label(spec)}")
        except OSError as exc:  # checked before; the target changed during the computation
            raise UserError(f"--plot = {args.plot}: cannot write there ({exc.strerror or exc})") from None
    if args.json:
        print(json.dumps(result.to_json(), allow_nan=False))
    else:
        print(format_summary(result, spec))
    return 0


def _z_range(P, status):
    """Axial range of the contact points on the flanks, or why there are none."""
    ok = np.isfinite(P[:, 2])
    if ok.any():
        return f"{P[ok, 2].min():.2f} .. {P[ok, 2].max():.2f}"
    st = list(status)
    if st.count(PointStatus.FAILED) == len(st):
        return "none (not solved)"
    return f"none ({st.count(PointStatus.OUTSIDE)} outside, {st.count(PointStatus.FAILED)} failed)"


def _play_range(bl) -> str:
    """The play at the reference angle and the largest, when the play varies over the cycle."""
    if bl.max_um is None or bl.max_um - bl.um < 5e-5:
        return "; the same at every angle"
    ref = "" if bl.at_reference_um is None else f"; {bl.at_reference_um:.4f} um at the left reference angle"
    return f"{ref}; up to {bl.max_um:.4f} um"


#: the statuses of a contact (counted apart where it carries the mesh and where it does not: idle)
CARRYING = (PointStatus.OK, PointStatus.EDGE)


def format_summary(result, spec) -> str:
    lines = [f"TCA of {spec.source} with {errors_label(spec)}", ""]
    head = ("flank", *CARRYING, "idle", *(s for s in PointStatus if s not in CARRYING), "pinion z range (mm)",
            "gear z range (mm)", "TE mean (urad)", "TE p-p (urad)", "Newton its (mean)", "TE points")
    rows = [head]
    caveats = []
    for flank, fr in result.flanks.items():
        st = np.array(fr.status)
        carrying = np.asarray(fr.active, dtype=bool)
        cnt = [str(int(((st == s) & carrying).sum())) for s in CARRYING]
        cnt.append(str(int((np.isin(st, CARRYING) & ~carrying).sum())))
        cnt += [str(int((st == s).sum())) for s in PointStatus if s not in CARRYING]
        pairs = len(set(fr.tooth_pair.tolist()))
        positions = len(st) // pairs
        te = fr.transmission_error[fr.active & np.isfinite(fr.transmission_error)]
        carried = (fr.active & np.isfinite(fr.transmission_error)).reshape(pairs, positions).any(axis=0)
        n_te = int((carried & fr.te_envelope_complete).sum())
        mean = number(te.mean() * 1e6, ".3f") if te.size else "-"
        ptp = (number(fr.te_peak_to_peak * 1e6, ".3e") if np.isfinite(fr.te_peak_to_peak)
               else "n/a" if positions == 1 else "-")
        its = fr.newton_iterations_mean
        rows.append((flank, *cnt, _z_range(fr.pinion_contact, st), _z_range(fr.gear_contact, st), mean, ptp,
                     "-" if its is None else f"{its:.2f}", f"{n_te}/{positions}"))
        if 0 < n_te < int(fr.te_envelope_complete.sum()):
            caveats.append(f"{flank} flank: TE peak-to-peak from {n_te} of {positions} positions only (no"
                           f" contact on the flanks at the others): it does not describe a whole mesh cycle")
    w = [max(len(r[i]) for r in rows) for i in range(len(head))]
    lines += ["  ".join(c.rjust(wi) if i else c.ljust(wi) for i, (c, wi) in enumerate(zip(r, w))) for r in rows]
    if result.backlash is not None:
        b = result.backlash
        if b.um is None:
            lines += ["", f"backlash: not measured ({b.status}: {b.reason})"]
        else:
            lines += ["", f"backlash at the gear's working pitch circle: {number(b.um, '.4f')} um (smallest play over a mesh"
                          f" cycle{_play_range(b)}; positive: play, negative: the flanks interfere)"]
    lines += [f"note: {n}" for n in [*caveats, *result.notes]]
    lines += ["", "z: axial position in the member frame (toe -> heel); of the "
              f"{len(result.flanks[next(iter(result.flanks))].status)} pair-positions: ok, edge: a surface or edge"
              " contact that carries the mesh (the envelope of the pairs); idle: a contact of a pair that carries"
              " nothing there (the pair carrying holds it off); outside, failed: no contact; TE points: pinion"
              " positions where the TE envelope is carried and complete (no tooth pair beyond those solved"
              " can carry there; the TE p-p is taken over these), of all positions"]
    return "\n".join(lines)

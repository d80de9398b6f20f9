"""``beveloid design FILE [--json] [--plot OUT.png]``: direct pitch-cone design from a TOML spec.

``configure(parser)`` adds the arguments; ``run(args) -> int`` prints the Table 1 layout
(:func:`beveloid.design.format_table1`) and the whole-tooth checks
(:mod:`beveloid.tooth.report`) or, with ``--json``, the JSON of
:func:`beveloid.design.design_json` with the whole-tooth fields on stdout and returns 0;
``--plot`` draws the transverse sections (:mod:`beveloid.tooth.plot`).  Invalid input and
infeasible designs raise :class:`beveloid.spec.SpecError` / :class:`beveloid.design.DesignError`;
the main CLI turns them into a one-line message and exit status 2.
"""
from __future__ import annotations

import argparse
import json
import sys


def configure(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("file", metavar="FILE", help="TOML design spec (`beveloid example case1` prints one)")
    parser.add_argument("--json", action="store_true",
                        help="print the design as JSON on stdout (nothing else on stdout)")
    parser.add_argument("--plot", metavar="OUT.png",
                        help="draw transverse sections of both members at toe, middle and heel (beveloid.tooth)")


def run(args: argparse.Namespace) -> int:
    """Direct pitch-cone design from a TOML spec.

    Prints a table laid out like the paper's Table 1 (angles in degrees), or JSON with --json.
    """
    from ..design import design_json, format_table1
    from ..pair import Pair
    from ..tooth import report
    from .paths import check_output_file

    if args.plot is not None:
        check_output_file(args.plot, "--plot", ".png")  # before anything is computed
    pair = Pair.from_spec(args.file)
    result = pair.design
    tooth = report.analyze(pair)  # whole-tooth checks: statuses, not refusals
    if args.plot is not None:
        from ..tooth import plot

        plot.plot_sections(pair, tooth, args.plot)
    warning = unusable_warning(result, tooth)
    if warning:
        print(f"beveloid design: WARNING: {warning}", file=sys.stderr)
    if args.json:
        print(json.dumps(tooth.add_to(design_json(result)), indent=2, allow_nan=False))
    else:
        print((f"WARNING: {warning}\n\n" if warning else "") + format_table1(result) + "\n" + tooth.table())
    return 0


def unusable_warning(result, tooth) -> str:
    """One line when the unmodified pair does not mesh continuously on either flank (its contact ratio below 1
    on both), with the numbers in which a unit slip shows (the working pressure angle, the mounting
    distances); "" otherwise."""
    import math

    from ..status import ToothStatus

    below = [m for s, m in tooth.statuses if s == ToothStatus.CONTACT_RATIO_BELOW_ONE]
    if not below or len(below) < len(tooth.contact_ratio):
        return ""
    ratios = ", ".join(f"{fl} {v:.3f}" for fl, v in tooth.contact_ratio.items())
    d = ", ".join(f"{m} {getattr(result, m).mounting_distance_mm:.1f} mm" for m in ("pinion", "gear"))
    return (f"not a usable pair as it stands: the contact ratio is below 1 on both flanks ({ratios}), the working"
            f" normal pressure angle is {math.degrees(result.working_normal_pressure_angle):.2f} deg (rack"
            f" {math.degrees(result.normal_pressure_angle):g} deg), the mounting distances {d}; check"
            " pair.normal_module_mm and pair.offset_mm (both in mm) against the teeth")

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
    if args.json:
        print(json.dumps(tooth.add_to(design_json(result)), indent=2, allow_nan=False))
    else:
        print(format_table1(result) + "\n" + tooth.table())
    return 0

"""``beveloid paper [--out DIR] [--positions N]``: Table 1 and the studies of Figs 10-22 into DIR."""
from __future__ import annotations

import argparse

from ..errors import UserError


def configure(p: argparse.ArgumentParser) -> None:
    p.add_argument("--out", default="paper_out", metavar="DIR", help="output folder (default paper_out)")
    p.add_argument("--positions", type=int, default=200, metavar="N",
                   help="pinion positions per error set (default 200)")
    p.add_argument("--tooth-model", choices=("fe", "plate"), default=None,
                   help="the loaded contact's tooth (Figs 24-25): fe (default) or plate, as in beveloid ltca")


def run(args: argparse.Namespace) -> int:
    """Reproduce Table 1 and the studies of Figs 10-22 into DIR (PNG, CSV, report.md)."""
    from ..studies.paper import run as reproduce
    from .paths import check_output_dir

    if not 10 <= args.positions <= 5000:
        raise UserError(f"--positions = {args.positions}: must be an integer from 10 to 5000")
    check_output_dir(args.out, "--out")
    try:
        reproduce(args.out, positions=args.positions, tooth_model=args.tooth_model)
    except OSError as exc:
        raise UserError(f"--out = {args.out}: cannot write there ({exc.strerror})") from None
    return 0

"""``beveloid paper [--out DIR] [--positions N]``: every study of :data:`beveloid.studies.PAPER_CONTENTS`
into DIR (the help's first line is built from it)."""
from __future__ import annotations

import argparse
import sys

from ..errors import UserError
from ..studies import PAPER_CONTENTS


def configure(p: argparse.ArgumentParser) -> None:
    p.add_argument("--out", default="paper_out", metavar="DIR", help="output folder (default paper_out)")
    p.add_argument("--positions", type=int, default=200, metavar="N",
                   help="pinion positions per error set (default 200)")
    from .common import add_ltca_flags

    add_ltca_flags(p, only=("tooth_model",))  # the loaded contact's tooth (Figs 24-25), as beveloid ltca takes it


def run(args: argparse.Namespace) -> int:
    """Reproduce the paper into DIR (PNG, CSV, report.md): see the first line of --help."""
    from ..outputs import interrupted_note
    from ..parallel import WorkLost
    from ..studies.paper import run as reproduce
    from .paths import check_output_dir

    if not 10 <= args.positions <= 5000:
        raise UserError(f"--positions = {args.positions}: must be an integer from 10 to 5000")
    check_output_dir(args.out, "--out")
    try:
        reproduce(args.out, positions=args.positions, tooth_model=args.tooth_model)
    except KeyboardInterrupt:  # the files are moved into DIR only at the end (beveloid/studies/output.py)
        print(f"beveloid paper: {interrupted_note(args.out, '--out')}", file=sys.stderr, flush=True)
        raise
    except WorkLost as exc:  # a worker process died (killed by the out-of-memory killer, say): one line, exit 1
        print(f"beveloid paper: error: {exc}; {interrupted_note(args.out, '--out')}", file=sys.stderr, flush=True)
        return 1
    except OSError as exc:
        if exc.filename is None:  # not a file of DIR (e.g. a closed stdout): the CLI reports it
            raise
        raise UserError(f"--out = {args.out}: cannot write there ({exc.strerror})") from None
    return 0


run.__doc__ = f"Reproduce {PAPER_CONTENTS} into DIR (PNG, CSV, report.md)."

"""``beveloid derive [--check] [--no-docs]``: regenerate generated/ and docs/derivations.md.

Imports sympy and the derivations only when it runs.
"""
from __future__ import annotations

import argparse
import sys

from ..errors import UserError


def configure(p: argparse.ArgumentParser) -> None:
    p.add_argument("--check", action="store_true",
                   help="regenerate in memory and compare: exit 1 and print a unified diff when stale")
    p.add_argument("--no-docs", action="store_true",
                   help="generated/ only: leave docs/derivations.md out (and the ~20 s verification of Eqs 1-38 it shows)")


def run(args: argparse.Namespace) -> int:
    """Regenerate generated/ and docs/derivations.md from the symbolic models.

    With --check nothing is written: exit status 1 and a unified diff when a file is stale.
    With --no-docs only generated/ is regenerated (or compared).
    """
    from beveloid.derivations.derive import derive  # lazy: imports sympy

    def progress(what) -> None:
        print(f"generating {what} ...", file=sys.stderr, flush=True)

    try:
        diff, seconds = derive(check=args.check, progress=progress, docs_page=not args.no_docs)
    except FileNotFoundError as exc:
        raise UserError(str(exc)) from None
    if args.check:
        if diff:
            sys.stdout.write(diff)
            print("generated files are stale: run `beveloid derive` to update", file=sys.stderr)
            return 1
        what = "generated/ is" if args.no_docs else "generated/ and docs/derivations.md are"
        print(f"{what} up to date ({seconds:.1f} s)", file=sys.stderr)
        return 0
    print(f"regenerated in {seconds:.1f} s" + (" (files changed)" if diff else " (no change)"), file=sys.stderr)
    return 0

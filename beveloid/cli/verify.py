"""``beveloid verify [--json]``: every equation of the paper checked against the symbolic models.

Imports sympy and the derivations only when it runs.
"""
from __future__ import annotations

import argparse
import sys


def configure(p: argparse.ArgumentParser) -> None:
    p.add_argument("--json", action="store_true",
                   help="print the results as JSON on stdout (nothing else on stdout)")


def run(args: argparse.Namespace) -> int:
    """Check every equation of the paper against the symbolic models.

    Prints a table (or JSON with --json); exit status 1 if any equation differs.
    """
    from beveloid.derivations import registry  # lazy: imports sympy

    progress = None
    if sys.stderr.isatty():
        def progress(eq) -> None:
            print(f"checking Eq {eq.number} ...", file=sys.stderr, flush=True)

    _equations, results = registry.verify(progress=progress)
    results = list(results) + registry.verify_extra()  # beyond the print (not numbered "1".."38")
    if args.json:
        print(registry.results_json(results))
    else:
        print(registry.results_table(results))
    return 1 if any(r.status == "differs" for r in results) else 0

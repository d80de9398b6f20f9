"""``beveloid derive [--check] [--no-docs]``: regenerate generated/ and docs/derivations.md;
``beveloid derive --model FILE --name NAME [--out DIR]``: one model of your own into a model folder.

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
    p.add_argument("--model", metavar="FILE",
                   help="a derivation module of your own (docs/models.md): generate its kernels into a model folder,"
                        " check them and make them usable as tooth_surface = NAME (needs --name)")
    p.add_argument("--name", help="with --model: the model's name in specs (lower case, e.g. twisted)")
    p.add_argument("--out", metavar="DIR",
                   help="with --model: the model folder to write into (default: BEVELOID_MODELS_DIR, else the user"
                        " data folder's beveloid/models)")


def _progress(what) -> None:
    print(what if what.startswith("checking") else f"generating {what} ...", file=sys.stderr, flush=True)


def run(args: argparse.Namespace) -> int:
    """Regenerate generated/ and docs/derivations.md from the symbolic models (or --model: your own).

    With --check nothing is written: exit status 1 and a unified diff when a file is stale.
    With --no-docs only generated/ is regenerated (or compared).
    """
    if args.model is not None or args.name is not None or args.out is not None:
        return _run_model(args)
    from beveloid.derivations.derive import derive  # lazy: imports sympy

    try:  # --check only compares: no "generating" lines
        diff, seconds = derive(check=args.check, progress=None if args.check else _progress,
                               docs_page=not args.no_docs)
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


def _run_model(args: argparse.Namespace) -> int:
    if args.model is None or args.name is None:
        missing = "--model FILE" if args.model is None else "--name NAME"
        raise UserError(f"{missing} is missing: a model of your own needs both --model FILE and --name NAME")
    if args.check or args.no_docs:
        raise UserError(f"{'--check' if args.check else '--no-docs'} with --model: those apply to the built-in "
                        "derivation only; drop it")
    if args.out is not None:  # one rule for every output folder, before any work (cli/paths.py)
        from .paths import check_output_dir

        check_output_dir(args.out, "--out")
    from beveloid.derivations.user_model import ModelError, derive_model  # lazy: imports sympy

    try:
        done = derive_model(args.model, args.name, args.out, progress=_progress)
    except ModelError as exc:
        raise UserError(str(exc)) from None
    ok = all(c.passed for c in done.checks)
    print("checked:")
    for c in done.checks:
        print(f"  {'ok  ' if c.passed else 'FAIL'} {c.name}: {c.detail}")
    if not ok:
        print(f"model \"{args.name}\" NOT written: a check failed ({done.seconds:.1f} s)")
        return 1
    print(f"wrote model \"{args.name}\" to {done.folder}: {', '.join(done.files)} ({done.seconds:.1f} s)")
    keys = "; ".join(f"{k} ({u}, default {d:g}, {lo:g} to {hi:g})" for k, u, d, lo, hi, _ in done.keys)
    print(f"use it: tooth_surface = \"{args.name}\" in a [pinion] or [gear] section" + (f"; its keys: {keys}" if keys
                                                                                      else ""))
    return 0

"""``beveloid example [case1|case2] [--schema]``: a packaged example spec, or the key schema.

``beveloid example case1 > my.toml`` gives a starting point that works wherever the package is
installed (the examples ship in beveloid/data/); ``--schema`` prints every key of a spec file with
whether it is required, its default, its valid values and its meaning.
"""
from __future__ import annotations

import argparse
import sys

from ..spec import EXAMPLES


def configure(p: argparse.ArgumentParser) -> None:
    p.add_argument("name", nargs="?", choices=tuple(EXAMPLES), metavar="NAME",
                   help="which example: " + ", ".join(f"{k} ({v})" for k, v in EXAMPLES.items()))
    p.add_argument("--schema", action="store_true",
                   help="print every key of a spec file (required/default, valid values, meaning) instead")
    p.add_argument("--model", action="append", default=[], metavar="NAME",
                   help="with --schema: include the keys of this user model (repeatable; `beveloid models` lists them)")


def run(args: argparse.Namespace) -> int:
    """Print a packaged example spec (TOML) or, with --schema, the keys of a spec file.

    Start a design with `beveloid example case1 > my.toml`, then edit my.toml.
    """
    from ..errors import UserError
    from ..spec import example_text, key_schema_text

    if args.schema:
        if args.name is not None:
            raise UserError(f"NAME = {args.name} with --schema: give one of them, not both")
        _check_models(args.model)
        sys.stdout.write(key_schema_text(tuple(args.model)) + "\n")
        return 0
    if args.model:
        raise UserError(f"--model {args.model[0]} without --schema: --model selects the user model keys --schema prints")
    if args.name is None:
        raise UserError(f"NAME is missing: give one of {', '.join(EXAMPLES)} (or --schema for the keys)")
    sys.stdout.write(example_text(args.name))
    return 0


def _check_models(names) -> None:
    from ..errors import UserError
    from ..models import catalog

    cat = catalog()
    for name in names:
        problem = cat.problem(name)
        if problem:
            raise UserError(f"--model {name}: {problem}")

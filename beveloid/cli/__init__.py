"""Command line interface: ``beveloid <command> [options]``.

One module per command, ``beveloid/cli/<command>.py``, registered by name in :data:`COMMANDS`.
A command module has two functions:

    configure(parser)  adds the command's arguments to its sub-parser
    run(args) -> int   does the work and returns the exit status; the first line
                       of its docstring is the command's help text

Command modules are imported lazily: ``beveloid tca ...`` imports only ``cli/tca.py``;
``beveloid --help`` imports every command module (each one cheap: the work's imports sit
inside ``run``).  A new command is a new module here plus one name in :data:`COMMANDS`.

Exit status: 0 success; 1 the command ran but its result is negative (``verify``:
an equation differs from the print); 2 a usage error (argparse) or a user error
(:class:`beveloid.spec.SpecError`, :class:`beveloid.errors.UserError`), reported as
one line ``beveloid: error: <message>`` on stderr without a traceback.

This package must stay cheap to import: it imports neither sympy nor the
derivations at module level (``verify`` and ``derive`` load them when they run).
"""
from __future__ import annotations

import argparse
import importlib
import sys
from collections.abc import Sequence

from ..errors import UserError
from ..spec import SpecError

PROG = "beveloid"
USER_ERRORS = (SpecError, UserError)

#: The commands, in the order ``beveloid --help`` lists them; each is the module
#: ``beveloid.cli.<name>`` with ``configure(parser)`` and ``run(args) -> int``.
COMMANDS: tuple[str, ...] = ("verify", "derive", "design", "tca", "ltca", "paper", "sweep", "example")


def command(name: str):
    """The module of the command ``name`` (imported on first use)."""
    return importlib.import_module(f"{__name__}.{name}")


def _help_text(run) -> str:
    doc = (run.__doc__ or "").strip()
    return doc.splitlines()[0].rstrip(".") if doc else ""


def _version() -> str:
    # From the installed metadata rather than beveloid.__version__: works however the
    # package was installed (an editable install may map beveloid as a namespace).
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("beveloid")
    except PackageNotFoundError:
        return "unknown (not installed)"


class _OneLineParser(argparse.ArgumentParser):
    """Usage errors as one line (``beveloid <command>: error: ...; see --help``), exit 2."""

    def error(self, message):
        print(f"{self.prog}: error: {message} (see {self.prog} --help)", file=sys.stderr)
        raise SystemExit(2)


def build_parser(only: str | None = None) -> argparse.ArgumentParser:
    """The parser of every command, or of the command ``only`` alone (the others are not imported)."""
    parser = _OneLineParser(
        prog=PROG,
        description="Crossed beveloid gears after Zhu, Song, Lim & Peng, Mech. Mach. Theory 59 (2013).",
    )
    parser.add_argument("--version", action="version", version=f"{PROG} {_version()}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True, parser_class=_OneLineParser)
    for name in COMMANDS if only is None else (only,):
        module = command(name)
        help_text = _help_text(module.run)
        p = sub.add_parser(name, help=help_text, description=(module.run.__doc__ or "").strip())
        module.configure(p)
        p.set_defaults(_run=module.run)
    return parser


def _error(message: str) -> int:
    from ..spec import printable

    one_line = printable(" ".join(str(message).split()))  # no raw control characters on the terminal
    print(f"{PROG}: error: {one_line}", file=sys.stderr)
    return 2


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``beveloid`` script; returns the exit status."""
    argv = sys.argv[1:] if argv is None else list(argv)
    parser = build_parser(argv[0] if argv and argv[0] in COMMANDS else None)
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help, --version (0) and usage errors (2)
        return exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 2)
    try:
        return args._run(args)
    except USER_ERRORS as exc:
        return _error(str(exc))
    except BrokenPipeError:  # e.g. `beveloid tca ... --json | head`
        import os

        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except KeyboardInterrupt:
        print(f"{PROG}: interrupted", file=sys.stderr)
        return 130

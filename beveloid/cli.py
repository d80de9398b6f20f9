"""Command line interface: ``beveloid <command> [options]``.

Each command is a pair of small functions registered in :data:`COMMANDS`:

    configure(parser)  adds the command's arguments to its sub-parser
    run(args) -> int   does the work and returns the exit status; the first line
                       of its docstring is the command's help text

Exit status: 0 success; 1 the command ran but its result is negative (``verify``:
an equation differs from the print); 2 a usage error (argparse) or a user error
(:class:`beveloid.spec.SpecError`, :class:`beveloid.errors.UserError`), reported as
one line ``beveloid: error: <message>`` on stderr without a traceback.

This module must stay cheap to import: it imports neither sympy nor the
derivations at module level (``verify`` loads them when it runs).
"""
from __future__ import annotations

import argparse
import sys
from collections.abc import Callable, Sequence

from .errors import UserError
from .cli_design import configure as _design_configure
from .cli_design import run as _design_run
from .cli_example import configure as _example_configure
from .cli_example import run as _example_run
from .cli_sweep import configure as _sweep_configure
from .cli_sweep import run as _sweep_run
from .cli_ltca import configure as _ltca_configure
from .cli_ltca import run as _ltca_run
from .cli_tca import configure as _tca_configure
from .cli_tca import run as _tca_run
from .explore.command import configure as _explore_configure
from .explore.command import run as _explore_run
from .spec import SpecError

PROG = "beveloid"
USER_ERRORS = (SpecError, UserError)


# ---------------------------------------------------------------------------
# verify
# ---------------------------------------------------------------------------


def _configure_verify(p: argparse.ArgumentParser) -> None:
    p.add_argument("--json", action="store_true",
                   help="print the results as JSON on stdout (nothing else on stdout)")


def _run_verify(args: argparse.Namespace) -> int:
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


# ---------------------------------------------------------------------------
# derive
# ---------------------------------------------------------------------------


def _configure_derive(p: argparse.ArgumentParser) -> None:
    p.add_argument("--check", action="store_true",
                   help="regenerate in memory and compare: exit 1 and print a unified diff when stale")
    p.add_argument("--no-docs", action="store_true",
                   help="generated/ only: leave docs/derivations.md out (and the ~20 s verification of Eqs 1-38 it shows)")


def _run_derive(args: argparse.Namespace) -> int:
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


# ---------------------------------------------------------------------------
# paper
# ---------------------------------------------------------------------------


def _configure_paper(p: argparse.ArgumentParser) -> None:
    p.add_argument("--out", default="paper_out", metavar="DIR", help="output folder (default paper_out)")
    p.add_argument("--positions", type=int, default=200, metavar="N",
                   help="pinion positions per error set (default 200)")


def _run_paper(args: argparse.Namespace) -> int:
    """Reproduce Table 1 and the studies of Figs 10-22 into DIR (PNG, CSV, report.md)."""
    from .reproduction import run

    from .cli_paths import check_output_dir

    if not 10 <= args.positions <= 5000:
        raise UserError(f"--positions = {args.positions}: must be an integer from 10 to 5000")
    check_output_dir(args.out, "--out")
    try:
        run(args.out, positions=args.positions)
    except OSError as exc:
        raise UserError(f"--out = {args.out}: cannot write there ({exc.strerror})") from None
    return 0


# ---------------------------------------------------------------------------
# Further commands go here, each as _configure_<name> / _run_<name> plus one
# entry in COMMANDS.  Planned, NOT implemented yet (do not register stubs):
#
#   derive  regenerate generated/ and docs/derivations.md from derivations/
#           (docs: beveloid.derivations.docs.write_derivations_md)
#   design  direct / indirect pitch-cone design from a TOML spec (beveloid.design)
#   tca     tooth contact analysis with assembly errors (beveloid.tca)
#   paper   reproduce Table 1 and the paper's figures
#   sweep   contact path / transmission error over a range of misalignments
# ---------------------------------------------------------------------------


Configure = Callable[[argparse.ArgumentParser], None]
Run = Callable[[argparse.Namespace], int]

#: name -> (configure, run)
COMMANDS: dict[str, tuple[Configure, Run]] = {
    "verify": (_configure_verify, _run_verify),
    "derive": (_configure_derive, _run_derive),
    "design": (_design_configure, _design_run),
    "tca": (_tca_configure, _tca_run),
    "ltca": (_ltca_configure, _ltca_run),
    "paper": (_configure_paper, _run_paper),
    "sweep": (_sweep_configure, _sweep_run),
    "example": (_example_configure, _example_run),
    "explore": (_explore_configure, _explore_run),
}


def _help_text(run: Run) -> str:
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


def build_parser() -> argparse.ArgumentParser:
    parser = _OneLineParser(
        prog=PROG,
        description="Crossed beveloid gears after Zhu, Song, Lim & Peng, Mech. Mach. Theory 59 (2013).",
    )
    parser.add_argument("--version", action="version", version=f"{PROG} {_version()}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True, parser_class=_OneLineParser)
    for name, (configure, run) in COMMANDS.items():
        help_text = _help_text(run)
        p = sub.add_parser(name, help=help_text, description=(run.__doc__ or "").strip())
        configure(p)
        p.set_defaults(_run=run)
    return parser


def _error(message: str) -> int:
    from .spec import printable

    one_line = printable(" ".join(str(message).split()))  # no raw control characters on the terminal
    print(f"{PROG}: error: {one_line}", file=sys.stderr)
    return 2


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``beveloid`` script; returns the exit status."""
    parser = build_parser()
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


if __name__ == "__main__":
    sys.exit(main())

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
an equation differs from the print) or its output could not be written (a closed stdout ``>&-``, a
full device ``>/dev/full``: one line on stderr, as Unix tools do); 2 a usage error (argparse) or a
user error (:class:`beveloid.spec.SpecError`, :class:`beveloid.errors.UserError`), reported as
one line ``beveloid: error: <message>`` on stderr without a traceback (a user's own model code that
failed: the frames of their file below it, :class:`beveloid.errors.UserCodeError`); 130 Ctrl-C.  A closed pipe
(``beveloid tca my.toml --json | head``) ends quietly with 0.  However a command ends, the output
folders it created and left empty are removed (:func:`beveloid.cli.paths.remove_empty_created`).

This package must stay cheap to import: it imports neither sympy nor the
derivations at module level (``verify`` and ``derive`` load them when they run).
"""
from __future__ import annotations

import argparse
import codecs
import errno
import gc
import importlib
import io
import os
import sys
import unicodedata
from collections.abc import Sequence

from .. import interrupts
from ..errors import UserError
from ..spec import SpecError

__all__ = ["main", "build_parser", "command", "COMMANDS", "PROG", "USER_ERRORS", "OUTPUT_ERRNOS"]

PROG = "beveloid"
USER_ERRORS = (SpecError, UserError)

#: The commands, in the order ``beveloid --help`` lists them; each is the module
#: ``beveloid.cli.<name>`` with ``configure(parser)`` and ``run(args) -> int``.
COMMANDS: tuple[str, ...] = ("verify", "derive", "design", "tca", "ltca", "paper", "sweep", "example", "export",
                             "explore", "rating", "fe-check", "models")


def command(name: str):
    """The module of the command ``name`` (imported on first use)."""
    return importlib.import_module(f"{__name__}.{name.replace('-', '_')}")  # fe-check: cli/fe_check.py


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


class _VersionAction(argparse.Action):
    """``--version``: the installed version, looked up only when asked (importlib.metadata: ~10 ms)."""

    def __init__(self, option_strings, dest=argparse.SUPPRESS, default=argparse.SUPPRESS, help=None):
        super().__init__(option_strings, dest=dest, default=default, nargs=0,
                         help=help or "show program's version number and exit")

    def __call__(self, parser, namespace, values, option_string=None):
        print(f"{PROG} {_version()}")  # on stdout, as argparse's own version action
        parser.exit()


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
    parser.add_argument("--version", action=_VersionAction)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True, parser_class=_OneLineParser)
    for name in COMMANDS if only is None else (only,):
        module = command(name)
        help_text = _help_text(module.run)
        p = sub.add_parser(name, help=help_text, description=(module.run.__doc__ or "").strip())
        module.configure(p)
        p.set_defaults(command_run=module.run)  # the parsed namespace names the function that runs it
    return parser


def _error(message: str, status: int = 2, frames=()) -> int:
    """``beveloid: error: <message>`` in one line; below it only ``frames``, the traceback lines of a
    user's own code that failed (:class:`beveloid.errors.UserCodeError`)."""
    from ..spec import printable

    one_line = printable(" ".join(str(message).split()))  # no raw control characters on the terminal
    print(f"{PROG}: error: {one_line}", file=sys.stderr)
    for line in frames:
        print(printable(line), file=sys.stderr)
    return status


class _ClosedStdout:
    """sys.stdout when the caller closed it (``>&-``): writing fails as writing to a closed file
    descriptor does (EBADF), so the command reports it; nothing is written at the exit."""

    encoding = "utf-8"
    errors = "strict"

    def write(self, text: str) -> int:
        if not text:
            return 0
        raise OSError(errno.EBADF, os.strerror(errno.EBADF))

    def flush(self) -> None:
        pass

    def isatty(self) -> bool:
        return False

    def fileno(self) -> int:
        raise io.UnsupportedOperation("stdout is closed")


#: errors of writing the output that are the place's, not the program's: one line and exit 1
OUTPUT_ERRNOS = frozenset(getattr(errno, n) for n in ("ENOSPC", "EIO", "EFBIG", "EDQUOT", "EROFS", "EBADF")
                          if hasattr(errno, n))


def _by_name(exc: UnicodeEncodeError) -> tuple[str, int]:
    """Codec error handler: a character the output's encoding lacks, by its name (``α`` -> ``alpha``)."""
    out = []
    for ch in exc.object[exc.start:exc.end]:
        name = unicodedata.name(ch, "")
        if name.startswith(("GREEK SMALL LETTER ", "GREEK CAPITAL LETTER ")):
            word = name.rsplit(" ", 1)[-1].lower()
            out.append(word if "SMALL" in name else word.capitalize())
        elif name.startswith("SUBSCRIPT ") or name.startswith("SUPERSCRIPT "):
            out.append(str(unicodedata.digit(ch, "")) or ch.encode("ascii", "backslashreplace").decode())
        else:
            out.append(ch.encode("ascii", "backslashreplace").decode("ascii"))
    return "".join(out), exc.end


codecs.register_error("beveloid-names", _by_name)


def _robust_environment() -> None:
    """Output in any terminal encoding, on closed streams, and a plotting backend that always works.

    Characters the stream's encoding lacks (Greek symbols with PYTHONIOENCODING=ascii) are written by
    name; every figure is a file, so matplotlib gets its file backend whatever MPLBACKEND says
    (beveloid.plots selects Agg too; an invalid MPLBACKEND would fail the import before that).
    """
    # a stdout closed by the caller (`beveloid tca my.toml >&-`) is None: writing to it fails as in
    # any Unix tool (one line, exit 1); its descriptor is held by the null device meanwhile, so that no
    # file opened later becomes descriptor 1.  A closed stderr is the null device (nothing to tell).
    if sys.stdout is None:
        _hold_descriptor(1)
        sys.stdout = _ClosedStdout()
    if sys.stderr is None:
        _hold_descriptor(2)
        sys.stderr = open(os.devnull, "w")  # noqa: SIM115
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.reconfigure(errors="beveloid-names")
        except (AttributeError, ValueError, OSError):  # not a TextIOWrapper (replaced, closed)
            pass
    if "MPLBACKEND" in os.environ:
        os.environ["MPLBACKEND"] = "agg"


def _hold_descriptor(fd: int) -> None:
    """Put the null device on the closed descriptor ``fd``."""
    try:
        null = os.open(os.devnull, os.O_WRONLY)
        if null != fd:
            os.dup2(null, fd)
            os.close(null)
    except OSError:
        pass


def _drop_stdout() -> None:
    """Point stdout at the null device: nothing more is written, nor flushed at exit."""
    try:
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
    except (OSError, ValueError):  # no file descriptor (a closed stdout, in-process callers' capture)
        sys.stdout = _ClosedStdout()


#: the script's threshold of young objects between collections (Python's default: 700): its imports
#: and numba's cache loading make ~10^5 objects that live to the end (a first compilation, millions),
#: and each young collection walks the ones made since the last (docs/performance.md)
GC_YOUNG_THRESHOLD = 50_000


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``beveloid`` script; returns the exit status.

    Without ``argv`` (the script, ``python -m beveloid.cli``: the process ends right after) the
    objects left are moved out of the garbage collector's reach (``gc.freeze``), so the
    interpreter's exit does not walk the ~10^5 objects left, most numba's (~0.05 s of a 0.5 s
    command, docs/performance.md).  The exit still runs as usual (atexit, streams flushed, modules
    torn down); in-process callers, which pass ``argv``, keep a collected heap."""
    if argv is None:  # the script: a Ctrl-C swallowed by a callback still stops the run (interrupts.py)
        interrupts.install()
        gc.set_threshold(GC_YOUNG_THRESHOLD, *gc.get_threshold()[1:])
    status = _main(argv)
    if argv is None:
        gc.freeze()
    return status


def _main(argv: Sequence[str] | None) -> int:
    _robust_environment()
    argv = sys.argv[1:] if argv is None else list(argv)
    parser = build_parser(argv[0] if argv and argv[0] in COMMANDS else None)
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help, --version (0) and usage errors (2)
        return exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 2)
    from .paths import remove_empty_created

    try:
        with interrupts.guard():  # a Ctrl-C that a callback swallowed: the run still says it was interrupted
            status = args.command_run(args)
        sys.stdout.flush()  # a full or failing output shows here, not at the interpreter's exit
        return status
    except USER_ERRORS as exc:
        return _error(str(exc), frames=getattr(exc, "frames", ()))
    except BrokenPipeError:  # e.g. `beveloid tca ... --json | head`
        _drop_stdout()
        return 0
    except OSError as exc:  # stdout closed (>&-), on a full disk (/dev/full), a failing device
        if exc.errno not in OUTPUT_ERRNOS:
            raise
        _drop_stdout()
        return _error(f"cannot write the output: {exc.strerror or exc} (errno {exc.errno})", status=1)
    except KeyboardInterrupt:
        print(f"{PROG}: interrupted", file=sys.stderr)
        return 130
    finally:
        remove_empty_created()

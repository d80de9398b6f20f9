"""Output targets (the CLI's ``--plot FILE``, ``--out DIR``; the API's ``out_dir``), checked before any
computation: one rule for every output, in the runtime so that the API keeps it too (beveloid.export).

``check_output_file(path, flag, suffix)`` and ``check_output_dir(path, flag)`` raise
:class:`OutputError` (a UserError, code ``ErrorCode.OUTPUT``: one line naming the flag, the value and
what would be valid) for: an empty name, a NUL byte, a name component longer than the file system
allows (NAME_MAX bytes) or a path longer than PATH_MAX, a folder given where a file is wanted (and
the reverse), an existing file or folder that is not writable, and a missing or unwritable parent
folder.  A folder that does not exist yet is acceptable when its parent is an existing, writable
folder (it is created: only the last folder of the path, never a missing tree).  ``flag`` names the
target in the message: a command-line flag (``--out``) or an option's name (``out_dir``).
"""
from __future__ import annotations

import os
from pathlib import Path

from .errors import ErrorCode, UserError
from .spec import printable

__all__ = ["OutputError", "check_output_file", "check_output_dir", "created_here", "interrupted_files_note",
           "interrupted_note", "remove_empty_created"]


class OutputError(UserError):
    """An output target that cannot be written (the message names it, its value and what would do)."""

    code = ErrorCode.OUTPUT


#: folders this process created for its outputs, in the order made
_CREATED: list[Path] = []
#: the name of :func:`_probe`'s empty file (the rest of its name random)
PROBE_PREFIX = ".beveloid-probe-"


def _limit(folder: Path, name: str, default: int) -> int:
    try:
        return int(os.pathconf(folder, name))
    except (OSError, ValueError, AttributeError):
        return default


def _exists(p: Path) -> bool:
    try:
        return p.exists()
    except OSError:  # e.g. a name too long: it cannot exist
        return False


def _nearest_existing(p: Path) -> Path:
    p = p.absolute()
    while not _exists(p) and p != p.parent:
        p = p.parent
    return p


def _common_checks(path: str, flag: str) -> Path:
    shown = printable(path, 80)
    if not path or not path.strip():
        raise OutputError(f"{flag} = \"{shown}\": an empty name; give a file or folder name")
    if "\0" in path:
        raise OutputError(f"{flag} = {shown}: contains a NUL character; give a plain file or folder name")
    p = Path(path)
    anchor = _nearest_existing(p)
    if anchor != p.absolute() and not anchor.is_dir():
        raise OutputError(f"{flag} = {shown}: the folder {printable(str(p.parent), 80)} does not exist"
                        f" ({printable(str(anchor), 80)} is a file); choose a path inside a folder")
    if not anchor.is_dir():
        anchor = anchor.parent
    name_max = _limit(anchor, "PC_NAME_MAX", 255)
    for part in p.parts:
        n = len(os.fsencode(part))
        if n > name_max:
            raise OutputError(f"{flag} = {shown}: the name {printable(part, 24)} has {n} bytes, more than the"
                            f" {name_max} the file system allows; choose a shorter name")
    path_max = _limit(anchor, "PC_PATH_MAX", 4096)
    if len(os.fsencode(str(p.absolute()))) >= path_max:
        raise OutputError(f"{flag} = {shown}: the path is longer than the {path_max} bytes the file system allows;"
                        " choose a shorter path")
    return p


def check_output_file(path: str, flag: str, suffix: str | None = None) -> None:
    """``path`` can be written as a file (its folder exists and is writable; if it exists it is a writable file)."""
    p = _common_checks(path, flag)
    shown = printable(path, 80)
    if suffix is not None and p.suffix.lower() != suffix:
        raise OutputError(f"{flag} = {shown}: the output is written as {suffix[1:].upper()}; give a file name"
                        f" ending in {suffix}")
    if p.is_dir():
        raise OutputError(f"{flag} = {shown}: is a folder; give a file name inside it, e.g. {shown}/out{suffix or ''}")
    folder = p.parent if str(p.parent) else Path(".")
    if not folder.is_dir():
        _create(folder, flag, shown)
    if p.exists() and not os.access(p, os.W_OK):
        raise OutputError(f"{flag} = {shown}: the file exists and is not writable; choose another name")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise OutputError(f"{flag} = {shown}: the folder {printable(str(folder), 80)} is not writable;"
                        " choose another")
    _probe(folder, flag, shown)


def _probe(folder: Path, flag: str, shown: str) -> None:
    """Create and remove an empty file in ``folder``: permissions say yes where a pseudo file system (/proc,
    /sys) or a read-only mount still refuses a new file, found here, not after the computation."""
    import tempfile

    try:
        with tempfile.NamedTemporaryFile(dir=folder, prefix=PROBE_PREFIX):
            pass
    except OSError as exc:
        raise OutputError(f"{flag} = {shown}: cannot create a file in {printable(str(folder), 80)}"
                          f" ({exc.strerror or exc}); choose another folder") from None


def check_output_dir(path: str, flag: str) -> None:
    """``path`` is a writable folder afterwards: an existing one, or one created in its existing,
    writable parent."""
    p = _common_checks(path, flag)
    shown = printable(path, 80)
    if p.exists() and not p.is_dir():
        raise OutputError(f"{flag} = {shown}: exists and is not a folder; give a new or existing folder")
    if not p.exists():
        _create(p, flag, shown)
    if not os.access(p, os.W_OK | os.X_OK):
        raise OutputError(f"{flag} = {shown}: the folder {printable(str(p), 80)} is not writable;"
                        " choose another")
    _probe(p, flag, shown)


def _create(folder: Path, flag: str, shown: str) -> None:
    """Make ``folder`` (one level: its parent must be an existing, writable folder) and remember it."""
    parent = folder.parent if str(folder.parent) else Path(".")
    where = printable(str(parent), 80)
    if not parent.is_dir():
        raise OutputError(f"{flag} = {shown}: the folder {where} does not exist; create it first or choose"
                        " a folder whose parent exists (only the last folder of the path is created)")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise OutputError(f"{flag} = {shown}: cannot create {printable(folder.name, 40)} in {where}: the folder is"
                        " not writable; choose another")
    try:
        folder.mkdir()
    except FileExistsError:  # made meanwhile by another process: use it
        if not folder.is_dir():
            raise OutputError(f"{flag} = {shown}: exists and is not a folder; choose another") from None
        return
    except OSError as exc:  # a read-only file system, a pseudo file system (/proc), ...
        raise OutputError(f"{flag} = {shown}: cannot create the folder ({exc.strerror or exc}); choose another"
                        ) from None
    _CREATED.append(folder.absolute())


def created_here(path: str | os.PathLike) -> bool:
    """Whether this process created the folder ``path`` for its outputs."""
    return Path(path).absolute() in _CREATED


def remove_empty_created() -> list[Path]:
    """Remove the folders this process created for its outputs and left empty (the last made first);
    returns them.  A folder that holds anything stays; a probe file of :func:`_probe` left in it does not
    count (a Ctrl-C right after the folder was made can stop the probe between the file's creation and its
    removal: the folder then held only that file and stayed, seen in tests/cli/test_cli_outputs.py)."""
    import contextlib

    removed = []
    while _CREATED:
        folder = _CREATED.pop()
        for probe in folder.glob(PROBE_PREFIX + "*"):
            with contextlib.suppress(OSError):
                probe.unlink()
        try:
            folder.rmdir()
        except OSError:  # not empty, or gone
            continue
        removed.append(folder)
    return removed


def interrupted_note(path: str | os.PathLike, flag: str) -> str:
    """What a command says when a Ctrl-C stopped it before it moved its files into the folder ``path``
    (they are written into a folder of their own first, beveloid/studies/output.py): nothing is kept,
    and the folder is removed if this process made it (the CLI removes it on its way out)."""
    shown = printable(str(path), 80)
    if created_here(path):
        return f"{flag} = {shown}: nothing written (the folder, made by this run, is removed)"
    return f"{flag} = {shown}: nothing written (the folder is as it was before the run)"


def interrupted_files_note(path: str | os.PathLike, flag: str, removed: list) -> str:
    """What a command says when a Ctrl-C stopped it after it had written the files ``removed`` (names)
    into the folder ``path`` and it removed them again (they are partial): nothing is kept."""
    if not removed:
        return interrupted_note(path, flag)
    shown = printable(str(path), 80)
    where = ("the folder, made by this run, is removed" if created_here(path)
             else "the folder keeps its other files")
    return f"{flag} = {shown}: nothing kept: removed the partial {', '.join(removed)} ({where})"

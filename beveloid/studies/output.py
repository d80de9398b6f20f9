"""An output folder that two runs can share: each run writes into its own hidden folder inside the
target, and moves its files into place only when it has finished, one run at a time.

Without it, two ``beveloid paper --out same`` runs at once leave a folder mixed from both (the report
of one, figures of the other).  With it the folder holds one complete run's files (the one that
finished last), and a run that fails leaves the folder as it was.
"""
from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path

from .. import interrupts
from ..outputs import check_output_dir

#: name prefix of a run's folder while it writes (hidden, removed when the run ends)
STAGE_PREFIX = ".beveloid-partial-"


@contextlib.contextmanager
def _locked(folder: Path) -> Iterator[None]:
    """An exclusive lock on ``folder`` (flock on its descriptor; released if the process dies)."""
    try:
        import fcntl
    except ImportError:  # not POSIX: the moves are still per file and atomic
        yield
        return
    fd = os.open(folder, os.O_RDONLY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        os.close(fd)  # releases the lock


@contextlib.contextmanager
def staged_folder(target: str | os.PathLike) -> Iterator[Path]:
    """A fresh folder to write into; on success its files replace those of the same name in ``target``.

    The folder lies inside ``target`` (created if missing, by the one output rule: its parent must
    exist, beveloid/outputs.py), so the moves stay on one file system and need no more permissions
    than writing into ``target`` itself.
    """
    check_output_dir(str(target), "out_dir")
    target = Path(target)
    stage = Path(tempfile.mkdtemp(prefix=STAGE_PREFIX, dir=target))
    try:
        yield stage
        interrupts.check()  # a Ctrl-C swallowed on the way (beveloid/interrupts.py): nothing is moved
        with _locked(target):
            for item in sorted(stage.iterdir()):
                os.replace(item, target / item.name)
    finally:
        shutil.rmtree(stage, ignore_errors=True)

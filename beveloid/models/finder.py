"""The import hook's entry: cheap to import (``import beveloid`` installs it).  The work — finding
models, composing the glue — is in :mod:`.hook`, imported on the first import of a glue module."""
from __future__ import annotations

import sys

from .names import GLUE, PACKAGE


class Finder:
    """A meta path finder (duck-typed: importlib.abc costs ~0.1 s to import) for beveloid.generated."""

    def find_spec(self, fullname, path=None, target=None):
        if not fullname.startswith(PACKAGE + "."):
            return None
        short = fullname[len(PACKAGE) + 1:]
        if short.startswith("_") or "." in short or (short not in GLUE and not short.startswith(("surface_", "layout_"))):
            return None
        from .hook import served_spec

        return served_spec(fullname, short)


def install() -> None:
    """Put the hook in front of the import system (once)."""
    if not any(isinstance(f, Finder) for f in sys.meta_path):
        sys.meta_path.insert(0, Finder())

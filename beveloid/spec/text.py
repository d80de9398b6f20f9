"""Values and names as they appear in a one-line error message (printable, bounded, TOML-like)."""
from __future__ import annotations

import datetime
import difflib
from collections.abc import Mapping
from typing import Any

from .model import one_line


def fmt_value(value: Any) -> str:
    """Render an offending value on one line, TOML-like."""
    if value is None:
        return "None"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        text = str(value)
        return text if len(text) <= 30 else text[:12] + "..." + text[-6:]
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, str):
        text = value if len(value) <= 40 else value[:37] + "..."
        return '"' + text.encode("unicode_escape").decode("ascii").replace('"', '\\"') + '"'
    if isinstance(value, (datetime.date, datetime.time)):  # datetime is a date too
        kind = ("a date-time" if isinstance(value, datetime.datetime)
                else "a date" if isinstance(value, datetime.date) else "a time")
        return f"{value.isoformat()} ({kind})"
    if isinstance(value, Mapping):
        return "a table {" + ", ".join(name_text(k) for k in list(value)[:5]) + ("...}" if len(value) > 5 else "}")
    if isinstance(value, (list, tuple)):
        text = "[" + ", ".join(fmt_value(v) for v in list(value)[:5]) + (", ...]" if len(value) > 5 else "]")
        return text
    text = repr(value)
    return one_line(text if len(text) <= 40 else text[:37] + "...")


def printable(text: str, limit: int | None = None) -> str:
    """``text`` with every non-printable character escaped (NUL, ESC, newlines ...), optionally shortened."""
    text = str(text)
    if limit is not None and len(text) > limit:
        text = text[: limit - 3] + "..."
    if text.isprintable():
        return text
    return "".join(c if c.isprintable() else c.encode("unicode_escape").decode("ascii") for c in text)


def name_text(key: Any) -> str:
    """A key or section name as it may appear in a message: printable, at most 40 characters."""
    return printable(str(key), 40)


def closest(name: str, candidates: list[str]) -> str | None:
    """Most likely intended key: a close spelling, else a unique key starting with ``name``."""
    lowered = {c.lower(): c for c in candidates}
    close = difflib.get_close_matches(name.lower(), list(lowered), n=1, cutoff=0.6)
    if close:
        return lowered[close[0]]
    prefixed = [c for c in candidates if name and c.lower().startswith(name.lower())]
    return prefixed[0] if len(prefixed) == 1 else None


def hint(name: str, candidates: list[str]) -> str:
    match = closest(name, candidates)
    return f" (did you mean {match}?)" if match else ""

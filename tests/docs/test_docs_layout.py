"""docs/layout.md names every package and top-level module of beveloid/, and nothing that does not exist.

The page's file tree is one fenced block: a folder of the checkout at the start of a line, its
entries indented by two spaces (a file ``name.py`` or a folder ``name/``, then what it holds, which
may go on over lines indented further).  Every entry exists; every ``name.py`` an entry's text
names (without a folder before it) exists in that entry's folder, or in the top-level folder for
files; ``<...>`` and ``*`` in a name stand for any text.
"""
from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
LAYOUT = ROOT / "docs" / "layout.md"


def tree() -> dict:
    """{top-level folder: {entry: its text}} of the layout's first fenced block."""
    text = LAYOUT.read_text(encoding="utf-8")
    block = text.split("```")[1]
    out, top, entry = {}, None, None
    for line in block.splitlines():
        if not line.strip():
            continue
        if not line.startswith(" "):
            top, entry = line.split()[0], None
            out[top] = {}
        elif re.match(r"  \S", line):
            entry = line.split()[0].rstrip(",")
            out[top][entry] = line
        else:
            assert entry is not None, f"docs/layout.md: a continuation line before any entry: {line!r}"
            out[top][entry] += "\n" + line
    return out


def _exists(folder: Path, name: str) -> bool:
    pattern = re.sub(r"<[^>]*>", "*", name.rstrip("/"))
    found = list(folder.glob(pattern))
    return any(p.is_dir() for p in found) if name.endswith("/") else any(p.is_file() for p in found)


def test_the_layout_names_every_package_and_top_level_module_of_the_runtime():
    entries = set(tree()["beveloid/"])
    packages = {p.parent.name + "/" for p in (ROOT / "beveloid").glob("*/__init__.py")}
    modules = {p.name for p in (ROOT / "beveloid").glob("*.py")}
    missing = (packages | modules) - entries
    assert not missing, f"docs/layout.md leaves out these parts of beveloid/: {sorted(missing)}"


def test_everything_the_layout_names_exists():
    absent = []
    for top, entries in tree().items():
        folder = ROOT / top.rstrip("/")
        if not folder.is_dir():
            absent.append(top)
            continue
        for entry, text in entries.items():
            if not _exists(folder, entry):
                absent.append(top + entry)
                continue
            # files named in the entry's text: in the entry's folder (a package), else beside the entry
            where = folder / entry.rstrip("/") if entry.endswith("/") else folder
            for name in re.findall(r"(?<![\w/.<>*-])([\w<>*]+\.py)\b", text.split(None, 1)[1] if " " in text else ""):
                if not _exists(where, name):
                    absent.append(f"{(where / name).relative_to(ROOT)} (in the line of {top}{entry})")
    assert not absent, f"docs/layout.md names what does not exist: {absent}"


def test_the_layout_reader_finds_entries_and_their_lines():
    t = tree()
    assert {"derivations/", "generated/", "beveloid/", "tests/", "docs/", "benchmarks/", "examples/"} <= set(t)
    assert "solver/" in t["beveloid/"] and "chord.py" in t["beveloid/"]["solver/"]  # a continuation line
    assert _exists(ROOT / "generated", "surface_<model>.py") and not _exists(ROOT / "generated", "surface_<m>/")

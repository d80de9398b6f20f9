"""README.md stays true: the Quickstart commands, CI running the same command, the key table."""
from __future__ import annotations

import os
import re
from pathlib import Path

from beveloid.spec import key_docs_markdown

REPO = Path(__file__).resolve().parent.parent
README = (REPO / "README.md").read_text(encoding="utf-8")


def _section(title: str) -> str:
    m = re.search(rf"^## {re.escape(title)}\n(.*?)(?=^## |\Z)", README, flags=re.M | re.S)
    assert m, f"README has no '## {title}' section"
    return m.group(1)


def test_quickstart_is_two_commands_and_ci_runs_the_second():
    blocks = re.findall(r"^```[^\n]*\n(.*?)^```", _section("Quickstart"), flags=re.M | re.S)
    assert len(blocks) == 1, "Quickstart must hold a single code block"
    commands = [line for line in blocks[0].splitlines() if line.strip()]
    assert len(commands) == 2
    assert commands[0].startswith("pip install . && beveloid ")
    # `pytest`, not `python -m pytest`: the latter would import the bare checkout's beveloid/
    assert commands[1] == 'pip install ".[test]" && pytest'
    ci = REPO / ".ci" / "run"
    assert os.access(ci, os.X_OK), ".ci/run must be executable"
    ci_lines = [line.strip() for line in ci.read_text(encoding="utf-8").splitlines()]
    assert commands[1] in ci_lines, ".ci/run must run the README's second Quickstart command verbatim"


def test_input_key_table_is_current():
    assert key_docs_markdown().strip() in _section("Input keys"), (
        "README's key table differs from beveloid.spec.key_docs_markdown(): paste its output")


def test_python_api_example_runs(monkeypatch):
    """The README's Python API block runs as written (from the repository root)."""
    blocks = re.findall(r"^```python\n(.*?)^```", _section("Python API"), flags=re.M | re.S)
    assert len(blocks) == 1
    monkeypatch.chdir(REPO)
    ns = {}
    exec(compile(blocks[0], "README.md (Python API)", "exec"), ns)
    assert ns["res"].backlash_um is not None
    assert ns["mc"].contact_points_solved == 10_000 * 50
    assert abs(ns["back"].offset_mm - ns["d"].offset_mm) < 1e-9 * ns["d"].offset_mm


def test_packaged_examples_match_the_examples_folder():
    """beveloid/data/ ships copies of examples/*.toml for `beveloid paper`; they must not drift."""
    for name in ("case1.toml", "case2.toml"):
        assert (REPO / "beveloid" / "data" / name).read_bytes() == (REPO / "examples" / name).read_bytes(), name

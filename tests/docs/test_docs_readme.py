"""README.md stays true: the Quickstart commands, CI running the same command, the key table."""
from __future__ import annotations

import os
import re
from pathlib import Path

from beveloid.spec import key_docs_markdown

REPO = Path(__file__).resolve().parents[2]
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


def test_python_api_example_runs(monkeypatch, tmp_path):
    """The README's Python API block runs as written, from any working directory (here an empty one)."""
    blocks = re.findall(r"^```python\n(.*?)^```", _section("Python API"), flags=re.M | re.S)
    assert len(blocks) == 1
    monkeypatch.chdir(tmp_path)
    ns = {}
    exec(compile(blocks[0], "README.md (Python API)", "exec"), ns)
    assert ns["res"].backlash_um is not None
    assert ns["mc"].contact_points_solved == 2_000 * 20
    assert abs(ns["back"].offset_mm - ns["d"].offset_mm) < 1e-9 * ns["d"].offset_mm
    assert ns["d"] is ns["pair"].design and ns["geom"] is ns["pair"].geometry
    assert list(ns["shifted"].errors) == [0.5, 0.0, 0.0, 0.0, 0.0]
    assert ns["right"].status.count("ok") > 0 and ns["k"].k1 >= ns["k"].k2


def test_packaged_examples_match_the_examples_folder():
    """beveloid/data/ ships copies of examples/*.toml for `beveloid paper`; they must not drift."""
    for name in ("case1.toml", "case2.toml"):
        assert (REPO / "beveloid" / "data" / name).read_bytes() == (REPO / "examples" / name).read_bytes(), name


def _command_rows() -> dict[str, str]:
    """command name -> the README command-table row that documents it."""
    rows = {}
    for line in _section("Commands").splitlines():
        m = re.match(r"^\| `beveloid ([\w-]+)", line)
        if m:
            assert m.group(1) not in rows, f"two rows for {m.group(1)}"
            rows[m.group(1)] = line
    return rows


def test_command_table_is_complete():
    """Every subcommand of the parser has a row, every row a subcommand, and every flag of a
    subcommand (except -h/--help) appears in its row, with its choices where it has them."""
    from beveloid import cli

    parser = cli.build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    rows = _command_rows()
    assert set(rows) == set(sub.choices), (sorted(rows), sorted(sub.choices))
    for name, p in sub.choices.items():
        synopsis = rows[name].split(" | ")[0]
        for action in p._actions:
            flags = [o for o in action.option_strings if o not in ("-h", "--help")]
            for flag in flags:
                assert re.search(rf"{re.escape(flag)}(?![\w-])", synopsis), f"{name}: {flag} missing from README"
            if action.choices and action.option_strings:
                for choice in action.choices:
                    assert choice in synopsis, f"{name} {flags}: choice {choice} missing from README"
            if not action.option_strings and action.choices:  # a positional with choices (example NAME)
                for choice in action.choices:
                    assert choice in synopsis, f"{name}: {choice} missing from README"


def test_help_does_not_point_into_a_checkout():
    """An installed user has no examples/ folder: no --help text may send them there."""
    from beveloid import cli

    parser = cli.build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    texts = [parser.format_help()] + [p.format_help() for p in sub.choices.values()]
    for text in texts:
        assert "examples/" not in text, text
    assert "beveloid example case1" in " ".join(sub.choices["design"].format_help().split())

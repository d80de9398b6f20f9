"""README.md and the docs pages it points to stay true: the Quickstart commands, CI running the same
command, the short command table (README) and the reference (docs/commands.md), the key table
(docs/input.md), the Python API example (docs/api.md), the README's length and links."""
from __future__ import annotations

import os
import re
from pathlib import Path

from beveloid.spec import key_docs_markdown

REPO = Path(__file__).resolve().parents[2]
README = (REPO / "README.md").read_text(encoding="utf-8")
COMMANDS_MD = (REPO / "docs" / "commands.md").read_text(encoding="utf-8")
#: how the README's command table marks a command that is announced but not yet in the parser
IN_PROGRESS = "(in progress)"


def _section(title: str, text: str = README, name: str = "README") -> str:
    m = re.search(rf"^## {re.escape(title)}\n(.*?)(?=^## |\Z)", text, flags=re.M | re.S)
    assert m, f"{name} has no '## {title}' section"
    return m.group(1)


def test_quickstart_is_two_commands_and_ci_runs_the_second():
    blocks = re.findall(r"^```[^\n]*\n(.*?)^```", _section("Quickstart"), flags=re.M | re.S)
    assert len(blocks) == 1, "Quickstart must hold a single code block"
    commands = [line for line in blocks[0].splitlines() if line.strip()]
    assert len(commands) == 2
    assert commands[0].startswith("pip install . && beveloid ")
    # `pytest`, not `python -m pytest`: the latter would import the bare checkout's beveloid/
    # uv installs the test extras (~13 s against pip's ~66 s on the same machine: docs/performance.md, "Test suite")
    # into the Python that `python3` is: a venv's when one is active, as pip would
    assert commands[1] == 'pip install uv && uv pip install --python "$(command -v python3)" ".[test]" && pytest'
    ci = REPO / ".ci" / "run"
    assert os.access(ci, os.X_OK), ".ci/run must be executable"
    ci_lines = [line.strip() for line in ci.read_text(encoding="utf-8").splitlines()]
    assert commands[1] in ci_lines, ".ci/run must run the README's second Quickstart command verbatim"
    # and the end-to-end tests that command leaves out (pyproject.toml's marker "slow"), after it
    assert ci_lines.index("pytest -m slow") > ci_lines.index(commands[1]), ".ci/run must run `pytest -m slow` too"


def test_input_key_table_is_current():
    text = (REPO / "docs" / "input.md").read_text(encoding="utf-8")
    assert key_docs_markdown().strip() in _section("Keys", text, "docs/input.md"), (
        "docs/input.md's key table differs from beveloid.spec.key_docs_markdown(): paste its output")


def test_packaged_examples_match_the_examples_folder():
    """beveloid/data/ ships copies of examples/*.toml for `beveloid paper`; they must not drift."""
    for name in ("case1.toml", "case2.toml"):
        assert (REPO / "beveloid" / "data" / name).read_bytes() == (REPO / "examples" / name).read_bytes(), name


def _command_rows() -> dict[str, str]:
    """command name -> the README command-table row that names it."""
    rows = {}
    for line in _section("Commands").splitlines():
        m = re.match(r"^\| `beveloid ([\w-]+)", line)
        if m:
            assert m.group(1) not in rows, f"two rows for {m.group(1)}"
            rows[m.group(1)] = line
    return rows


def _subcommands() -> dict:
    from beveloid import cli

    parser = cli.build_parser()
    return next(a for a in parser._actions if a.dest == "command").choices


def test_readme_command_table_is_complete_and_short():
    """Every subcommand has a one-line row in the README; a row for a command the parser does not
    have yet says so; the rows stay short (the options are in docs/commands.md)."""
    sub = _subcommands()
    rows = _command_rows()
    assert set(sub) <= set(rows), f"commands without a README row: {sorted(set(sub) - set(rows))}"
    for name, row in rows.items():
        assert (name in sub) != (IN_PROGRESS in row), (
            f"{name}: a row is marked {IN_PROGRESS} exactly when the parser lacks the command")
        assert len(row) <= 160, f"{name}: the README row is long; put the detail in docs/commands.md"


def _reference_synopses() -> dict[str, str]:
    """command name -> the synopsis line(s) of its section in docs/commands.md."""
    out = {}
    for m in re.finditer(r"^## ([\w-]+)\n\n(`beveloid .*?)\n\n", COMMANDS_MD, flags=re.M | re.S):
        out[m.group(1)] = m.group(2)
    return out


def test_command_reference_is_complete():
    """docs/commands.md has a section per subcommand, and every flag of a subcommand (except
    -h/--help) appears in its synopsis, with its choices where it has them."""
    sub = _subcommands()
    synopses = _reference_synopses()
    assert set(sub) <= set(synopses), f"no section in docs/commands.md: {sorted(set(sub) - set(synopses))}"
    for name, p in sub.items():
        synopsis = synopses[name]
        for action in p._actions:
            flags = [o for o in action.option_strings if o not in ("-h", "--help")]
            for flag in flags:
                assert re.search(rf"{re.escape(flag)}(?![\w-])", synopsis), f"{name}: {flag} missing"
            if action.choices and action.option_strings:
                for choice in action.choices:
                    assert choice in synopsis, f"{name} {flags}: choice {choice} missing from docs/commands.md"
            if not action.option_strings and action.choices:  # a positional with choices (example NAME)
                for choice in action.choices:
                    assert choice in synopsis, f"{name}: {choice} missing from docs/commands.md"


def test_readme_is_short_and_its_links_exist():
    """A newcomer reads it in five minutes: under 8 KB, and every relative link resolves."""
    assert len(README.encode()) < 8_000, f"README.md has {len(README.encode())} bytes"
    for target in re.findall(r"\]\(([^)#]+)(?:#[^)]*)?\)", README):
        if "://" not in target:
            assert (REPO / target).exists(), f"README links to a missing {target}"
    for page in ("commands.md", "input.md", "api.md", "findings.md", "layout.md"):
        text = (REPO / "docs" / page).read_text(encoding="utf-8")
        for target in re.findall(r"\]\(([^)#]+)(?:#[^)]*)?\)", text):
            if "://" not in target:
                assert (REPO / "docs" / target).exists(), f"docs/{page} links to a missing {target}"


def test_readme_says_how_to_get_calculix():
    assert "apt-get install -y calculix-ccx" in README and "fe-check" in README


def test_readme_rows_name_the_extras_their_commands_need():
    """After the Quickstart's plain `pip install .`, `beveloid export` needs an extra: its row says which."""
    import tomllib

    from beveloid.export.formats import WRITERS

    optional = tomllib.loads((REPO / "pyproject.toml").read_text(encoding="utf-8"))["project"]["optional-dependencies"]
    extras = {w.extra for w in WRITERS.values()}
    assert extras <= set(optional), extras
    row = _command_rows()["export"]
    for extra in extras:
        assert f"`{extra}` extra" in row and f'pip install ".[{extra}]"' in row, row


def test_help_does_not_point_into_a_checkout():
    """An installed user has no examples/ folder: no --help text may send them there."""
    from beveloid import cli

    parser = cli.build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    texts = [parser.format_help()] + [p.format_help() for p in sub.choices.values()]
    for text in texts:
        assert "examples/" not in text, text
    assert "beveloid example case1" in " ".join(sub.choices["design"].format_help().split())


def test_files_the_docs_name_exist():
    """README, pyproject.toml and docs/*.md name files of the checkout; each must still be there."""
    pattern = re.compile(r"(?<![\w/.-])((?:beveloid|benchmarks|tests|derivations|generated|docs|examples)/[\w./-]*\w)")
    pages = [REPO / "README.md", REPO / "pyproject.toml", *sorted((REPO / "docs").glob("*.md"))]
    missing = []
    for page in pages:
        for name in pattern.findall(page.read_text(encoding="utf-8")):
            if "NN" in name or name.startswith("docs/images/") and not name.endswith((".png", ".py")):
                continue  # a pattern (derivations/eqNN_MM_*.py)
            if not (REPO / name).exists():
                missing.append(f"{page.relative_to(REPO)}: {name}")
    assert not missing, "named files that do not exist:\n" + "\n".join(missing)

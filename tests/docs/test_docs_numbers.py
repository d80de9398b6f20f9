"""The numbers the docs quote are the numbers the code gives now (issue 29, item 9; issue 41, 5).

docs/readme_numbers.py lists every quoted number with its page.  The cheap ones are computed here
(package constants, one TCA of case 1); the expensive ones (the worked exploration, the
verification's counts, the FE tooth against the plate, the ratings, the CalculiX runs) come from
docs/numbers.json, which `python docs/readme_numbers.py --record [GROUPS]` writes by running the
commands it names.  Whether the FE records are still the code's is tests/fe/test_fe_docs_canary.py's
check (on the session's coarse FE data); the CalculiX records are checked for presence and format."""
from __future__ import annotations

import importlib.util
import json
import re
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def numbers():
    spec = importlib.util.spec_from_file_location("readme_numbers", REPO / "docs" / "readme_numbers.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_every_quoted_number_is_current(numbers):
    """... and computing them leaves ``sys.path`` as it was: with the checkout first on it, the worker processes
    a later test of this process spawns (``beveloid.parallel``) imported the checkout's beveloid, not the
    installed one, and each compiled the solver afresh (~90-125 s of CPU each in the README's test command)."""
    path = list(sys.path)
    rec = numbers.recorded()
    # the FE groups' quotes (docs/loaded_contact.md 9.7, docs/validation.md 10 and 11) come from their records
    assert {"rating", "fe_tooth", "fe_check", "fe_sectors"} <= set(rec)
    wrong = []
    for page, text, holds in numbers.quotes(numbers.cheap_numbers(), rec):
        if text not in (REPO / page).read_text(encoding="utf-8") or not holds:
            wrong.append(f"{page}: {text!r}")
    assert not wrong, "stale numbers (see `python docs/readme_numbers.py --print`):\n" + "\n".join(wrong)
    assert sys.path == path, f"the quotes changed sys.path: {[p for p in sys.path if p not in path]} added"


def test_the_record_names_the_commands_that_made_it(numbers):
    """docs/numbers.json is strict JSON and was made by the commands the script runs now."""
    rec = json.loads((REPO / "docs" / "numbers.json").read_text(), parse_constant=lambda c: pytest.fail(c))
    assert rec["explore"]["command"] == "beveloid " + " ".join(numbers.EXPLORE_ARGS) + " --out case1_explore"
    assert rec["verify"]["command"] == "beveloid verify --json"
    assert rec["paper"]["command"] == "beveloid " + " ".join(numbers.PAPER_ARGS) + " --out paper_out"
    assert rec["verify"]["verified"] + rec["verify"]["definitions"] == rec["verify"]["equations"] == 38
    assert rec["rating"]["command"] == numbers.RATING_COMMAND
    assert rec["fe_tooth"]["command"] == "python -m benchmarks.bench_fe_tooth compare"
    # the CalculiX runs are the page's runs, each converged to numbers (null only where a pair is unloaded)
    runs = rec["fe_check"]["runs"]
    assert [(r["design"], r["flank"], r["torque_nm"], r["refinement"], r["coarsen"]) for r in runs] == \
        [tuple(run) for run in numbers.FE_CHECK_RUNS]
    for r in runs:
        assert r["calculix"]["loaded_transmission_error_urad"] > r["unloaded_transmission_error_urad"]
        assert all(v > 0 for v in r["calculix"]["root_stress_max_mpa"].values())


def test_readme_quotes_no_number_without_a_source():
    """The README keeps its numbers to the paper's equation range and the commands' names: timings and
    results live on the docs pages, each with its command."""

    text = (REPO / "README.md").read_text(encoding="utf-8")
    text = re.sub(r"`[^`]*`|\([^)]*\.(png|md)\)|!\[[^\]]*\]", "", text)  # code, links, image captions
    # the paper's equations, table and figures, the citation, "a 2-core machine"
    allowed = {"1–38", "1-38", "1", "10-22", "24-25", "48–64", "59", "2013", "2", "6336"}  # 6336: the ISO standard's number
    found = set(re.findall(r"\d+(?:[.,–-]\d+)*", text)) - allowed
    assert not found, f"numbers in the README without a source: {sorted(found)}"


#: a duration in prose: "95 s", "13-19 minutes", "two minutes", "about a minute"
_DURATION = re.compile(r"(?<![\w.])\d+(?:[.,]\d+)?(?:\s?[-–]\s?\d+(?:[.,]\d+)?)?\s?(?:s|min|minutes|seconds|hours?)\b"
                       r"|\b(?:a|one|two|three|a few|several) (?:minutes?|hours?)\b|\bminute\b")
#: how a paragraph states the load its timing was measured under
_LOAD = re.compile(r"load average|quiet|shared by|beside other work|whatever the\s+load")
#: the pages (and commands.md's sections) whose timings this test holds; commands.md's ltca, rating and
#: explore sections are their pages' own
TIMED_PAGES = ("docs/fe_check.md", "docs/models.md", "docs/input.md", "docs/commands.md")


def test_every_timing_states_its_load_and_its_command():
    """A time a page quotes says under what load it was measured and names the command or script that
    measured it (in the paragraph, or by docs/performance.md, which gives both); code blocks (a command's
    output) aside."""
    wrong = []
    for page in TIMED_PAGES:
        text = re.sub(r"^```.*?^```", "", (REPO / page).read_text(encoding="utf-8"), flags=re.M | re.S)
        if page.endswith("commands.md"):
            text = re.sub(r"^## (ltca|rating|explore)\n.*?(?=^## )", "", text, flags=re.M | re.S)
        for para in re.split(r"\n\s*\n|\n(?=\s*[*-] )|\n(?=\d+\. )", text):
            if _DURATION.search(para) and not (_LOAD.search(para) and ("`" in para or "performance.md" in para)):
                wrong.append(f"{page}: {' '.join(para.split())[:160]}")
    assert not wrong, "timings without their load and command:\n" + "\n".join(wrong)

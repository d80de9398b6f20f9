"""Numbers in the command tables (issue 29, item 11): nothing printed as `-0.000`."""
from __future__ import annotations

import re
from pathlib import Path

import pytest

from beveloid import cli
from beveloid.cli.common import number

REPO = Path(__file__).resolve().parents[2]
C1 = str(REPO / "examples" / "case1.toml")
NEGATIVE_ZERO = re.compile(r"-0\.0+(?![0-9])(?!e[+-]?0*[1-9])")


@pytest.mark.parametrize("value, spec, text", [(-1e-9, ".3f", "0.000"), (-4e-5, ".4f", "0.0000"),
                                               (-0.0, "+.3f", "+0.000"), (-0.0021, ".3f", "-0.002"),
                                               (-3e-12, ".2e", "-3.00e-12"), (float("nan"), ".3f", "-"),
                                               (None, ".1f", "-")])
def test_number_drops_the_sign_of_a_rounded_zero(value, spec, text):
    assert number(value, spec) == text


def test_tca_table_has_no_negative_zero(capsys):
    """Case 1 aligned: the TE is zero to round-off, of either sign (it printed -0.000)."""
    assert cli.main(["tca", C1, "--positions", "20"]) == 0
    out = capsys.readouterr().out
    assert "TE mean (urad)" in out
    assert not NEGATIVE_ZERO.search(out), NEGATIVE_ZERO.search(out).group(0)


def test_paper_and_sweep_name_their_path_measures_apart():
    """`paper`'s mean axial contact position and `sweep`'s path shift (the change from the aligned
    path) are different measures: no "path centre" left to confuse with "path shift"."""
    texts = [p.read_text(encoding="utf-8") for p in (REPO / "beveloid").rglob("*.py")]
    texts += [p.read_text(encoding="utf-8") for p in (REPO / "docs").glob("*.md")]
    assert not any(re.search(r"path cent(re|er)", t, flags=re.I) for t in texts)
    paper = (REPO / "beveloid" / "studies" / "paper.py").read_text(encoding="utf-8")
    assert "mean contact z (mm)" in paper and "not the path shift of `beveloid sweep`" in paper

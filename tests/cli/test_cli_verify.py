"""`beveloid verify` and the CLI's error policy (without re-running the verification: the session's fixture)."""
from __future__ import annotations

import argparse
import dataclasses
import json
import subprocess
import sys
import types
from pathlib import Path

import pytest

from beveloid import cli
from beveloid.errors import UserError
from beveloid.spec import SpecError

ALLOWED_STATUS = {"verified", "definition", "differs", "not checked", "not applicable"}


@pytest.fixture
def fake_verify(monkeypatch, verification):
    """Make registry.verify return the session's precomputed results (and call progress)."""
    from beveloid.derivations import registry

    state = {"verification": verification, "calls": 0}

    def verify(progress=None):
        state["calls"] += 1
        eqs, results = state["verification"]
        if progress:
            for e in eqs:
                progress(e)
        return eqs, results

    monkeypatch.setattr(registry, "verify", verify)
    return state


@pytest.fixture(scope="session")
def extra_checks():
    from beveloid.derivations import registry

    return registry.verify_extra()


def test_verify_json(fake_verify, extra_checks, capsys):
    rc = cli.main(["verify", "--json"])
    out, err = capsys.readouterr()
    assert fake_verify["calls"] == 1
    data = json.loads(out)  # stdout holds the JSON and nothing else
    numbered = [d for d in data if d["equation"].isdigit()]
    assert isinstance(data, list) and len(numbered) == 38
    assert sorted(d["equation"] for d in numbered) == sorted(str(n) for n in range(1, 39))
    # beyond the print: the FPD angle from the principal directions, one object per surface model
    extra = [d for d in data if not d["equation"].isdigit()]
    from beveloid.generated import surface_models
    assert sorted(d["equation"] for d in extra) == sorted(f"FPD-principal-directions:{m}" for m in surface_models.MODELS)
    assert all(d["status"] == "verified" for d in extra if d["equation"].endswith(":involute"))
    for d in data:
        assert set(d) >= {"equation", "title", "status", "method", "max_rel_diff", "note"}
        assert d["status"] in ALLOWED_STATUS
        if d["status"] == "differs":
            assert d["note"].strip(), f"Eq {d['equation']} differs without a note"
    assert rc == (1 if any(d["status"] == "differs" for d in data) else 0)
    assert err == ""  # not a TTY: no progress lines


def test_verify_table(fake_verify, extra_checks, capsys):
    rc = cli.main(["verify"])
    out, _err = capsys.readouterr()
    assert rc == 0
    assert out.splitlines()[0].split()[:2] == ["Eq", "what"]
    assert "(of 38 equations)" in out
    assert "FPD-principal-directions:involute" in out and "beyond the print:" in out


def test_the_summary_counts_only_applicable_checks():
    """`1 of 3 checks verified` read as two failures; two were not applicable."""
    from types import SimpleNamespace as R

    from beveloid.derivations.registry import extra_summary

    extra = [R(status="verified"), R(status="not applicable"), R(status="not applicable")]
    assert extra_summary(extra) == "beyond the print: 1 of 1 applicable check verified (2 not applicable)"
    assert extra_summary([R(status="verified"), R(status="differs")]) == (
        "beyond the print: 1 of 2 applicable checks verified, 1 differ")


def test_verify_progress_on_tty(fake_verify, capsys, monkeypatch):
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)
    cli.main(["verify", "--json"])
    out, err = capsys.readouterr()
    json.loads(out)
    assert err.splitlines() == [f"checking Eq {n} ..." for n in range(1, 39)]


def test_verify_exit_1_when_an_equation_differs(fake_verify, capsys):
    eqs, results = fake_verify["verification"]
    results = list(results)
    results[16] = dataclasses.replace(results[16], status="differs", max_rel_diff=1e-3, note="test")
    fake_verify["verification"] = (eqs, results)
    assert cli.main(["verify", "--json"]) == 1
    assert json.loads(capsys.readouterr().out)[16]["status"] == "differs"


# ---------------------------------------------------------------------------------------
# error policy
# ---------------------------------------------------------------------------------------


def _register_raising_command(monkeypatch, exc):
    """A command module ``beveloid.cli.boom`` whose run raises ``exc``, registered as "boom"."""
    def configure(p: argparse.ArgumentParser) -> None:
        pass

    def run(args):
        """Raise for the test."""
        raise exc

    module = types.ModuleType("beveloid.cli.boom")
    module.configure, module.run = configure, run
    monkeypatch.setitem(sys.modules, "beveloid.cli.boom", module)
    monkeypatch.setattr(cli, "COMMANDS", cli.COMMANDS + ("boom",))


@pytest.mark.parametrize("exc, message", [
    (SpecError("pinion.teeth = 5: must be an integer from 6 to 400", source="x.toml"),
     "x.toml: pinion.teeth = 5: must be an integer from 6 to 400"),
    (UserError("no such file:\n  design.toml"), "no such file: design.toml"),
])
def test_user_errors_are_one_line_exit_2(monkeypatch, capsys, exc, message):
    _register_raising_command(monkeypatch, exc)
    assert cli.main(["boom"]) == 2
    out, err = capsys.readouterr()
    assert out == ""
    assert err == f"beveloid: error: {message}\n"


def test_bugs_are_not_swallowed(monkeypatch):
    _register_raising_command(monkeypatch, ZeroDivisionError("bug"))
    with pytest.raises(ZeroDivisionError):
        cli.main(["boom"])


@pytest.mark.parametrize("argv", [[], ["nonsense"], ["verify", "--no-such-option"]])
def test_usage_errors_exit_2(argv, capsys):
    assert cli.main(argv) == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and "error:" in err and "--help" in err


def test_help_exits_0(capsys):
    assert cli.main(["--help"]) == 0
    assert "verify" in capsys.readouterr().out


def test_spec_error_is_independent_of_user_error():
    assert not issubclass(SpecError, UserError)
    assert issubclass(UserError, ValueError)


def test_cli_import_does_not_load_sympy(tmp_path):
    code = "import beveloid, beveloid.cli, sys; assert 'sympy' not in sys.modules, 'sympy was imported'"
    proc = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr


def test_the_fpd_check_of_crowned_flanks_is_not_applicable_with_its_reason():
    """The FPD theory assumes a straight-edged rack: the crowned model is not a failure to check."""
    from beveloid.derivations import fpd_principal_directions, registry
    from beveloid.derivations.kernels import SURFACE_MODELS

    (result,) = fpd_principal_directions.check(models={"crowned": SURFACE_MODELS["crowned"]})
    assert result.equation == "FPD-principal-directions:crowned"
    assert result.status == "not applicable" and result.max_rel_diff is None
    assert "straight-edged rack" in result.method and "straight-edged" in result.note
    (row,) = json.loads(registry.results_json([result]))
    assert row["status"] == "not applicable" and "straight-edged rack" in row["method"]
    assert "not applicable" in registry.results_table([result])
    docs = (Path(__file__).resolve().parents[2] / "docs" / "derivations.md").read_text(encoding="utf-8")
    crowned_row = next(line for line in docs.splitlines() if "('crowned' flanks)" in line)
    assert "| not applicable |" in crowned_row and "straight-edged rack" in crowned_row
